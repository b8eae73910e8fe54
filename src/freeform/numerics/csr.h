// Compressed sparse rows built and converted in parallel blocks of rows. Every row is computed
// on its own and every column keeps its row order, so the results have the bits of a serial
// build on any number of threads.
#pragma once

#include "freeform/common/parallel.h"

#include <Eigen/Sparse>

#include <algorithm>
#include <cstddef>
#include <exception>
#include <mutex>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

namespace freeform {

// Leaves new elements uninitialized: a large array is then first touched by the parallel loop
// that fills it, not by a serial memset.
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <class U>
  explicit UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  // Aggregates of plain data (whose member initializers would still write them) are left to
  // the storage's implicitly created objects.
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0) {
      if constexpr (!(std::is_aggregate_v<U> && std::is_trivially_copyable_v<U>)) ::new (static_cast<void*>(p)) U;
    } else
      ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

struct Csr {
  int rows = 0, cols = 0;
  std::vector<int> outer{0};
  std::vector<int, UninitializedAllocator<int>> inner;
  std::vector<double, UninitializedAllocator<double>> value;
  int row_size(int i) const { return outer[static_cast<std::size_t>(i) + 1] - outer[static_cast<std::size_t>(i)]; }
};

// Appends the entries of one block's rows; row_end[i - begin] is the block's entry count after
// row i.
struct CsrBlock {
  std::vector<int> inner;
  std::vector<double> value;
  std::vector<int> row_end;
};

// Rows [0, rows) of a rows x cols matrix: fill(begin, end, block) appends rows [begin, end) to
// the block, sorted by column, one row_end per row. Blocks of a fixed size run on the pool.
template <class Fill>
Csr build_csr(int rows, int cols, const Fill& fill);

// Rows [0, rows) of lhs * diag(w) * rhs (Gustavson, sorted rows). Columns of lhs beyond rhs.rows
// are empty rows of rhs. The pattern is structural: exact zeros (a right angle's cotangent,
// lambda = 0) stay, so the BCM system's pattern follows from the connectivity alone and can be
// ordered ahead (bcm/bcm_analysis.h).
Csr scaled_product(const Csr& lhs, const Eigen::VectorXd& w, const Csr& rhs, int rows);

// Columns [c0, c1) of x as a column-major matrix, scaled by `sign`; with drop_zeros, without
// its exact zeros.
Eigen::SparseMatrix<double> column_block(const Csr& x, int c0, int c1, double sign, bool drop_zeros);

namespace detail {
constexpr int kCsrBlockRows = 4096;
Csr join_blocks(int rows, int cols, std::vector<CsrBlock>& blocks);
}  // namespace detail

template <class Fill>
Csr build_csr(int rows, int cols, const Fill& fill) {
  const int n_blocks = (rows + detail::kCsrBlockRows - 1) / detail::kCsrBlockRows;
  std::vector<CsrBlock> blocks(static_cast<std::size_t>(n_blocks));
  // parallel_for's body must not throw: the first error (a block's bad_alloc) is rethrown here.
  std::exception_ptr error;
  std::mutex error_mutex;
  parallel_for(n_blocks, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    try {
      for (auto b = static_cast<int>(lo); b < hi; ++b) {
        const int begin = b * detail::kCsrBlockRows;
        fill(begin, std::min(rows, begin + detail::kCsrBlockRows), blocks[static_cast<std::size_t>(b)]);
      }
    } catch (...) {
      const std::scoped_lock lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  });
  if (error) std::rethrow_exception(error);
  return detail::join_blocks(rows, cols, blocks);
}

}  // namespace freeform
