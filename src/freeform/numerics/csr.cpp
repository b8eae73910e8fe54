#include "freeform/numerics/csr.h"

#include "freeform/common/parallel.h"

#include <algorithm>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <new>

namespace freeform {
namespace {

struct FreeDeleter {
  void operator()(void* p) const { std::free(p); }
};
template <class T>
using Buffer = std::unique_ptr<T[], FreeDeleter>;

// calloc: fresh pages stay untouched (and unzeroed by us) until a block writes them.
template <class T>
Buffer<T> zeroed(std::size_t n) {
  Buffer<T> out(static_cast<T*>(std::calloc(std::max<std::size_t>(n, 1), sizeof(T))));
  if (!out) throw std::bad_alloc();
  return out;
}

// One dense accumulator per running block, reused by the next block (fresh pages are slow to
// fault in, so a block must not allocate its own).
class Accumulators {
 public:
  struct Slot {
    Buffer<double> acc;
    Buffer<int> mark;  // row + 1 of the last row that touched the column, 0 never
  };
  explicit Accumulators(int cols) : cols_(cols) {}
  Slot* take() {
    const std::scoped_lock lock(mutex_);
    if (free_.empty()) {
      slots_.push_back(std::make_unique<Slot>(
          Slot{zeroed<double>(static_cast<std::size_t>(cols_)), zeroed<int>(static_cast<std::size_t>(cols_))}));
      return slots_.back().get();
    }
    Slot* s = free_.back();
    free_.pop_back();
    return s;
  }
  void give(Slot* s) {
    const std::scoped_lock lock(mutex_);
    free_.push_back(s);
  }

 private:
  int cols_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::vector<Slot*> free_;
};

// Row ranges for the passes of column_block: a few per thread, at least kCsrBlockRows rows each.
int transpose_blocks(int rows) {
  const int by_size = std::max(1, rows / detail::kCsrBlockRows);
  return std::min(by_size, 4 * (parallel_workers() + 1));
}

}  // namespace

namespace detail {

Csr join_blocks(int rows, int cols, std::vector<CsrBlock>& blocks) {
  Csr out;
  out.rows = rows;
  out.cols = cols;
  out.outer.resize(static_cast<std::size_t>(rows) + 1);
  std::vector<std::size_t> start(blocks.size() + 1, 0);
  std::size_t row = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    for (int end : blocks[b].row_end) out.outer[++row] = static_cast<int>(start[b]) + end;
    start[b + 1] = start[b] + blocks[b].inner.size();
  }
  out.inner.resize(start.back());
  out.value.resize(start.back());
  parallel_for(static_cast<std::ptrdiff_t>(blocks.size()), 1, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto b = static_cast<std::size_t>(begin); b < static_cast<std::size_t>(end); ++b) {
      std::copy(blocks[b].inner.begin(), blocks[b].inner.end(),
                out.inner.begin() + static_cast<std::ptrdiff_t>(start[b]));
      std::copy(blocks[b].value.begin(), blocks[b].value.end(),
                out.value.begin() + static_cast<std::ptrdiff_t>(start[b]));
      blocks[b] = CsrBlock{};
    }
  });
  return out;
}

}  // namespace detail

Csr scaled_product(const Csr& lhs, const Eigen::VectorXd& w, const Csr& rhs, int rows) {
  Accumulators scratch(rhs.cols);
  return build_csr(rows, rhs.cols, [&](int begin, int end, CsrBlock& out) {
    Accumulators::Slot* s = scratch.take();
    std::vector<int> row_cols;
    for (int i = begin; i < end; ++i) {
      row_cols.clear();
      for (int t = lhs.outer[static_cast<std::size_t>(i)]; t < lhs.outer[static_cast<std::size_t>(i) + 1]; ++t) {
        const int j = lhs.inner[static_cast<std::size_t>(t)];
        if (j >= rhs.rows) continue;
        const double f = lhs.value[static_cast<std::size_t>(t)] * w[j];  // 0 kept: see csr.h
        for (int u = rhs.outer[static_cast<std::size_t>(j)]; u < rhs.outer[static_cast<std::size_t>(j) + 1]; ++u) {
          const auto col = static_cast<std::size_t>(rhs.inner[static_cast<std::size_t>(u)]);
          if (s->mark[col] != i + 1) {
            s->mark[col] = i + 1;
            s->acc[col] = 0.0;
            row_cols.push_back(static_cast<int>(col));
          }
          s->acc[col] += f * rhs.value[static_cast<std::size_t>(u)];
        }
      }
      std::sort(row_cols.begin(), row_cols.end());
      for (int col : row_cols) {
        out.inner.push_back(col);
        out.value.push_back(s->acc[static_cast<std::size_t>(col)]);
      }
      out.row_end.push_back(static_cast<int>(out.inner.size()));
    }
    scratch.give(s);
  });
}

Eigen::SparseMatrix<double> column_block(const Csr& x, int c0, int c1, double sign, bool drop_zeros) {
  const int width = c1 - c0;
  const int n_blocks = transpose_blocks(x.rows);
  auto first_row = [&](int b) { return static_cast<int>(static_cast<long>(x.rows) * b / n_blocks); };
  // Each block counts its entries per column; then those counts become the block's offsets
  // within each column, so every column lists its rows in increasing order.
  std::vector<Buffer<int>> count(static_cast<std::size_t>(n_blocks));
  // Allocated before the loops: their bodies must not throw.
  for (Buffer<int>& c : count) c = zeroed<int>(static_cast<std::size_t>(width));
  auto for_kept = [&](int b, auto&& f) {
    for (int i = first_row(b); i < first_row(b + 1); ++i)
      for (int t = x.outer[static_cast<std::size_t>(i)]; t < x.outer[static_cast<std::size_t>(i) + 1]; ++t) {
        const int col = x.inner[static_cast<std::size_t>(t)];
        const double v = x.value[static_cast<std::size_t>(t)];
        if (col < c0 || col >= c1 || (drop_zeros && v == 0.0)) continue;
        f(i, col - c0, v);
      }
  };
  parallel_for(n_blocks, 1, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto b = static_cast<int>(begin); b < end; ++b) {
      Buffer<int>& c = count[static_cast<std::size_t>(b)];
      for_kept(b, [&](int, int col, double) { ++c[static_cast<std::size_t>(col)]; });
    }
  });
  Eigen::SparseMatrix<double> out(x.rows, width);
  int* outer = out.outerIndexPtr();
  parallel_for(width, 16384, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto col = static_cast<std::size_t>(begin); col < static_cast<std::size_t>(end); ++col) {
      int run = 0;
      for (Buffer<int>& c : count)
        if (const int n = c[col]) {  // untouched pages are only read
          c[col] = run;
          run += n;
        }
      outer[col + 1] = run;
    }
  });
  for (int col = 0; col < width; ++col) outer[col + 1] += outer[col];
  out.resizeNonZeros(outer[width]);
  int* inner = out.innerIndexPtr();
  double* value = out.valuePtr();
  parallel_for(n_blocks, 1, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto b = static_cast<int>(begin); b < end; ++b) {
      Buffer<int>& c = count[static_cast<std::size_t>(b)];
      for_kept(b, [&](int i, int col, double v) {
        const int pos = outer[col] + c[static_cast<std::size_t>(col)]++;
        inner[pos] = i;
        value[pos] = sign * v;
      });
    }
  });
  return out;
}

}  // namespace freeform
