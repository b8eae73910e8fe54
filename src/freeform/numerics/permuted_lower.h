// The lower triangle of P A P' from the lower triangle of a symmetric A, both in compressed
// columns, built on the pool: CHOLMOD's factorization makes this copy first, on one thread and
// by two transposes (issue 43; docs/benchmarks.md). Each column is sorted by row, as CHOLMOD's
// copy is, so the factor has the same bits on any number of threads.
#pragma once

#include "freeform/numerics/csr.h"

#include <vector>

namespace freeform {

struct LowerCsc {
  std::vector<int> outer;  // columns + 1
  std::vector<int, UninitializedAllocator<int>> inner;
  std::vector<double, UninitializedAllocator<double>> value;
};

// perm[k] is the row of A that becomes row k of P A P' (CHOLMOD's L->Perm). Entries above the
// diagonal of A are ignored, as CHOLMOD ignores them for a lower-stored matrix.
LowerCsc permuted_lower(int n, const int* outer, const int* inner, const double* value, const int* perm);

}  // namespace freeform
