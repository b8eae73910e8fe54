// CHOLMOD's supernodal symbolic analysis for a given fill-reducing ordering, with the permuted
// copies of the matrix it needs made on the pool (permuted_lower.h). cholmod_analyze_p with
// CHOLMOD_GIVEN makes them by four transposes on one thread; the elimination tree, its
// postorders, the column counts and the supernodes are CHOLMOD's own calls, in its order, so
// the symbolic factor is the one cholmod_analyze_p returns, bit for bit (issue 43;
// docs/benchmarks.md). Only for translation units built with SuiteSparse.
#pragma once

#include <cholmod.h>

namespace freeform {

// `lower`: the pattern of a symmetric matrix's lower triangle (int indices, packed, sorted);
// perm[k] is the row that becomes row k before CHOLMOD's postorder. Uses `common`'s settings
// (postorder, supernodal parameters) and leaves its status, lnz and fl as cholmod_analyze_p
// does. Returns a supernodal symbolic factor, or null with common->status set on failure.
cholmod_factor* analyze_supernodal_given(const cholmod_sparse& lower, const int* perm, cholmod_common* common);

}  // namespace freeform
