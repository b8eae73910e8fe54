// The numeric LL' factorization of a supernodal factor, on several cores (issue 43). CHOLMOD's
// cholmod_super_numeric factors the supernodes one after the other, and only the BLAS inside
// the large ones runs in parallel: on a mesh's operators most of its time is serial. Here the
// subtrees of SupernodalSolve's schedule are factored concurrently, each supernode left-looking
// as CHOLMOD does (its descendants' updates gathered, then potrf and trsm), and then the
// supernodes above the subtrees in order, each one's columns split among the threads for the
// updates. Every column receives its updates in an order fixed by the tree alone, so the factor
// has the same bits on any number of threads (not CHOLMOD's bits: its sums run in another order).
#pragma once

#include "freeform/numerics/permuted_lower.h"
#include "freeform/numerics/supernodal_solve.h"

namespace freeform {

// Writes the values of `layout`'s factor (x: its xsize doubles) for the lower triangle `a` of
// P A P' (columns sorted by row) plus `shift` on the diagonal. Returns the column at which a
// pivot was not positive (CHOLMOD's L->minor; the factor is then incomplete), or n.
int supernodal_factorize(const SupernodalFactor& layout, double* x, const SupernodalSolve& schedule,
                         const TriangleCsc& a, double shift = 0.0);

}  // namespace freeform
