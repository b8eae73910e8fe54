#include "freeform/numerics/permuted_lower.h"

#include "freeform/common/parallel.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <utility>

namespace freeform {

namespace {

constexpr std::ptrdiff_t kColumns = 4096;  // columns of A per pool chunk

// Calls visit(column, row, t) for every entry t of A's lower triangle in columns [begin, end):
// its place in the given triangle of P A P'.
template <class Visit>
void for_entries(std::ptrdiff_t begin, std::ptrdiff_t end, const int* outer, const int* inner, const int* inverse,
                 Triangle triangle, const Visit& visit) {
  for (auto j = static_cast<int>(begin); j < end; ++j)
    for (int t = outer[j]; t < outer[j + 1]; ++t) {
      const int i = inner[t];
      if (i < j) continue;
      const int a = std::min(inverse[i], inverse[j]), b = std::max(inverse[i], inverse[j]);
      if (triangle == Triangle::lower)
        visit(a, b, t);
      else
        visit(b, a, t);
    }
}

// Sorts m entries (rows, and values unless null) by row in place: insertion for the usual short
// columns, heapsort for long ones.
void sort_by_row(int* row, double* value, std::size_t m) {
  const auto swap_entries = [&](std::size_t a, std::size_t b) {
    std::swap(row[a], row[b]);
    if (value) std::swap(value[a], value[b]);
  };
  if (m <= 48) {
    for (std::size_t a = 1; a < m; ++a) {
      const int r = row[a];
      const double v = value ? value[a] : 0.0;
      std::size_t b = a;
      for (; b > 0 && row[b - 1] > r; --b) {
        row[b] = row[b - 1];
        if (value) value[b] = value[b - 1];
      }
      row[b] = r;
      if (value) value[b] = v;
    }
    return;
  }
  const auto sift_down = [&](std::size_t root, std::size_t size) {
    for (std::size_t child; (child = 2 * root + 1) < size; root = child) {
      if (child + 1 < size && row[child + 1] > row[child]) ++child;
      if (row[root] >= row[child]) return;
      swap_entries(root, child);
    }
  };
  for (std::size_t r = m / 2; r-- > 0;) sift_down(r, m);
  for (std::size_t size = m; size-- > 1;) {
    swap_entries(0, size);
    sift_down(0, size);
  }
}

}  // namespace

TriangleCsc permuted_triangle(int n, const int* outer, const int* inner, const double* value, const int* perm,
                              Triangle triangle) {
  TriangleCsc out;
  std::vector<int> inverse(static_cast<std::size_t>(n));
  parallel_for(n, 1 << 16, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto k = begin; k < end; ++k) inverse[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);
  });
  std::vector<int> fill(static_cast<std::size_t>(n) + 1, 0);
  parallel_for(n, kColumns, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for_entries(begin, end, outer, inner, inverse.data(), triangle, [&](int column, int, int) {
      std::atomic_ref<int>(fill[static_cast<std::size_t>(column) + 1]).fetch_add(1, std::memory_order_relaxed);
    });
  });
  for (int c = 0; c < n; ++c) fill[static_cast<std::size_t>(c) + 1] += fill[static_cast<std::size_t>(c)];
  out.outer = fill;
  const auto nonzeros = static_cast<std::size_t>(fill.back());
  out.inner.resize(nonzeros);
  if (value) out.value.resize(nonzeros);
  parallel_for(n, kColumns, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for_entries(begin, end, outer, inner, inverse.data(), triangle, [&](int column, int row, int t) {
      const auto slot = static_cast<std::size_t>(
          std::atomic_ref<int>(fill[static_cast<std::size_t>(column)]).fetch_add(1, std::memory_order_relaxed));
      out.inner[slot] = row;
      if (value) out.value[slot] = value[t];
    });
  });
  // The scatter's order within a column depends on the threads; the rows, all distinct, do not.
  parallel_for(n, kColumns, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto c = begin; c < end; ++c) {
      const auto first = static_cast<std::size_t>(out.outer[static_cast<std::size_t>(c)]);
      const auto last = static_cast<std::size_t>(out.outer[static_cast<std::size_t>(c) + 1]);
      sort_by_row(out.inner.data() + first, value ? out.value.data() + first : nullptr, last - first);
    }
  });
  return out;
}

}  // namespace freeform
