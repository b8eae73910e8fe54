// The lower (or upper) triangle of P A P' from the lower triangle of a symmetric A, both in
// compressed columns, built on the pool: CHOLMOD's factorization makes the lower one first, and
// its symbolic analysis both, twice, each on one thread by transposes (issue 43;
// docs/benchmarks.md). Each column is sorted by row, as CHOLMOD's copies are, so the analysis
// and the factor have the same bits on any number of threads.
#pragma once

#include "freeform/numerics/csr.h"

#include <vector>

namespace freeform {

struct TriangleCsc {
  std::vector<int> outer;  // columns + 1
  std::vector<int, UninitializedAllocator<int>> inner;
  std::vector<double, UninitializedAllocator<double>> value;  // empty for a pattern
};

enum class Triangle { lower, upper };

// perm[k] is the row of A that becomes row k of P A P' (CHOLMOD's L->Perm). Entries above the
// diagonal of A are ignored, as CHOLMOD ignores them for a lower-stored matrix. value null: the
// pattern alone.
TriangleCsc permuted_triangle(int n, const int* outer, const int* inner, const double* value, const int* perm,
                              Triangle triangle);
inline TriangleCsc permuted_lower(int n, const int* outer, const int* inner, const double* value, const int* perm) {
  return permuted_triangle(n, outer, inner, value, perm, Triangle::lower);
}

}  // namespace freeform
