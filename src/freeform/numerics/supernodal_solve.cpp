#include "freeform/numerics/supernodal_solve.h"

#include "freeform/common/cpu_features.h"
#include "freeform/common/parallel.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <optional>
#include <queue>
#include <utility>

namespace freeform {

// y: n rows of mp doubles (the right-hand sides padded to whole vectors), row-major.
struct detail::SupernodalSweep {
  double* y;
  int mp;
  bool wide;
};

namespace {

using Sweep = detail::SupernodalSweep;

// Subtrees are split until none holds more than this share of the factor: enough for 16 cores
// to balance, and the top of the tree they leave (the solve's serial part) stays a few percent.
constexpr double kSubtreeShare = 1.0 / 64.0;

struct Block {
  int ncol, nrow;
  const int* rows;
  const double* l;  // nrow by ncol, column-major
};

Block block(const SupernodalFactor& f, int s) {
  return {f.super[s + 1] - f.super[s], f.pi[s + 1] - f.pi[s], f.s_rows + f.pi[s], f.x + f.px[s]};
}

// The dense part of a supernode: x is its rows by W right-hand sides, row-major with leading
// dimension ld. Columns go four at a time, so that each row below is loaded and stored once
// per four columns of the factor (the solve is bound by reading the factor, not by flops).
// forward: on entry the first ncol rows hold the right-hand side and the others 0; on exit the
// first ncol rows hold L11^-1 of it and the others -L21 times that.
// backward: on entry the own rows hold the right-hand side and the others the solution; on exit
// the own rows hold L11^-T (rhs - L21^T others).
// The baseline ISA's version; AVX2 + FMA below.
template <int W>
void forward(const double* l, int nrow, int ncol, double* x, int ld) {
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    for (int q = 0; q < g; ++q) {
      const double* lc = l + static_cast<std::ptrdiff_t>(c0 + q) * nrow;
      double* xc = x + static_cast<std::ptrdiff_t>(c0 + q) * ld;
      const double d = lc[c0 + q];
      for (int k = 0; k < W; ++k) xc[k] /= d;
      for (int q2 = q + 1; q2 < g; ++q2) {
        double* xr = x + static_cast<std::ptrdiff_t>(c0 + q2) * ld;
        const double v = lc[c0 + q2];
        for (int k = 0; k < W; ++k) xr[k] -= v * xc[k];
      }
    }
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * nrow;
    if (g == 4) {
      const double *l1 = l0 + nrow, *l2 = l1 + nrow, *l3 = l2 + nrow;
      double p0[W], p1[W], p2[W], p3[W];
      for (int k = 0; k < W; ++k) {
        p0[k] = x[static_cast<std::ptrdiff_t>(c0) * ld + k];
        p1[k] = x[static_cast<std::ptrdiff_t>(c0 + 1) * ld + k];
        p2[k] = x[static_cast<std::ptrdiff_t>(c0 + 2) * ld + k];
        p3[k] = x[static_cast<std::ptrdiff_t>(c0 + 3) * ld + k];
      }
      for (int r = c0 + 4; r < nrow; ++r) {
        double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
        const double a0 = l0[r], a1 = l1[r], a2 = l2[r], a3 = l3[r];
        for (int k = 0; k < W; ++k) xr[k] -= a0 * p0[k] + a1 * p1[k] + a2 * p2[k] + a3 * p3[k];
      }
      continue;
    }
    for (int r = c0 + g; r < nrow; ++r) {
      double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
      for (int q = 0; q < g; ++q) {
        const double a = l0[static_cast<std::ptrdiff_t>(q) * nrow + r];
        const double* p = x + static_cast<std::ptrdiff_t>(c0 + q) * ld;
        for (int k = 0; k < W; ++k) xr[k] -= a * p[k];
      }
    }
  }
}
template <int W>
void backward(const double* l, int nrow, int ncol, double* x, int ld) {
  for (int c1 = ncol; c1 > 0; c1 -= 4) {
    const int c0 = std::max(0, c1 - 4), g = c1 - c0;
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * nrow;
    double acc[4][W] = {};
    if (g == 4) {
      const double *l1 = l0 + nrow, *l2 = l1 + nrow, *l3 = l2 + nrow;
      double s0[W] = {}, s1[W] = {}, s2[W] = {}, s3[W] = {};
      for (int r = c1; r < nrow; ++r) {
        const double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
        const double a0 = l0[r], a1 = l1[r], a2 = l2[r], a3 = l3[r];
        for (int k = 0; k < W; ++k) {
          s0[k] += a0 * xr[k];
          s1[k] += a1 * xr[k];
          s2[k] += a2 * xr[k];
          s3[k] += a3 * xr[k];
        }
      }
      for (int k = 0; k < W; ++k) acc[0][k] = s0[k], acc[1][k] = s1[k], acc[2][k] = s2[k], acc[3][k] = s3[k];
    } else {
      for (int r = c1; r < nrow; ++r) {
        const double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
        for (int q = 0; q < g; ++q) {
          const double a = l0[static_cast<std::ptrdiff_t>(q) * nrow + r];
          for (int k = 0; k < W; ++k) acc[q][k] += a * xr[k];
        }
      }
    }
    for (int q = g - 1; q >= 0; --q) {
      const double* lc = l0 + static_cast<std::ptrdiff_t>(q) * nrow;
      double* xc = x + static_cast<std::ptrdiff_t>(c0 + q) * ld;
      for (int q2 = q + 1; q2 < g; ++q2) {
        const double v = lc[c0 + q2];
        const double* xr = x + static_cast<std::ptrdiff_t>(c0 + q2) * ld;
        for (int k = 0; k < W; ++k) acc[q][k] += v * xr[k];
      }
      const double d = lc[c0 + q];
      for (int k = 0; k < W; ++k) xc[k] = (xc[k] - acc[q][k]) / d;
    }
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// The same kernels on AVX2 + FMA: a row chunk of W = 4 V doubles is V vectors.
namespace wide {

template <int V>
struct Row {
  __m256d v[V];
};

template <int V>
[[gnu::target("avx2,fma")]] inline Row<V> load(const double* p) {
  Row<V> r;
  for (int i = 0; i < V; ++i) r.v[i] = _mm256_loadu_pd(p + 4 * i);
  return r;
}

template <int V>
[[gnu::target("avx2,fma")]] inline void store(double* p, const Row<V>& r) {
  for (int i = 0; i < V; ++i) _mm256_storeu_pd(p + 4 * i, r.v[i]);
}

// r -= a * p, and r += a * p.
template <int V>
[[gnu::target("avx2,fma")]] inline void sub_scaled(Row<V>& r, double a, const Row<V>& p) {
  const __m256d s = _mm256_set1_pd(a);
  for (int i = 0; i < V; ++i) r.v[i] = _mm256_fnmadd_pd(s, p.v[i], r.v[i]);
}

template <int V>
[[gnu::target("avx2,fma")]] inline void add_scaled(Row<V>& r, double a, const Row<V>& p) {
  const __m256d s = _mm256_set1_pd(a);
  for (int i = 0; i < V; ++i) r.v[i] = _mm256_fmadd_pd(s, p.v[i], r.v[i]);
}

template <int V>
[[gnu::target("avx2,fma")]] inline void divide(Row<V>& r, double d) {
  const __m256d s = _mm256_set1_pd(d);
  for (int i = 0; i < V; ++i) r.v[i] = _mm256_div_pd(r.v[i], s);
}

template <int V>
[[gnu::target("avx2,fma")]] void forward(const double* l, int nrow, int ncol, double* x, int ld) {
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    Row<V> p[4] = {};
    for (int q = 0; q < g; ++q) {  // the 4 by 4 triangle
      const double* lc = l + static_cast<std::ptrdiff_t>(c0 + q) * nrow;
      p[q] = load<V>(x + static_cast<std::ptrdiff_t>(c0 + q) * ld);
      for (int q0 = 0; q0 < q; ++q0) sub_scaled(p[q], l[static_cast<std::ptrdiff_t>(c0 + q0) * nrow + c0 + q], p[q0]);
      divide(p[q], lc[c0 + q]);
      store(x + static_cast<std::ptrdiff_t>(c0 + q) * ld, p[q]);
    }
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * nrow;
    if (g == 4) {
      const double *l1 = l0 + nrow, *l2 = l1 + nrow, *l3 = l2 + nrow;
      for (int r = c0 + 4; r < nrow; ++r) {
        double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
        Row<V> a = load<V>(xr);
        sub_scaled(a, l0[r], p[0]);
        sub_scaled(a, l1[r], p[1]);
        sub_scaled(a, l2[r], p[2]);
        sub_scaled(a, l3[r], p[3]);
        store(xr, a);
      }
      continue;
    }
    for (int r = c0 + g; r < nrow; ++r) {
      double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
      Row<V> a = load<V>(xr);
      for (int q = 0; q < g; ++q) sub_scaled(a, l0[static_cast<std::ptrdiff_t>(q) * nrow + r], p[q]);
      store(xr, a);
    }
  }
}

template <int V>
[[gnu::target("avx2,fma")]] void backward(const double* l, int nrow, int ncol, double* x, int ld) {
  for (int c1 = ncol; c1 > 0; c1 -= 4) {
    const int c0 = std::max(0, c1 - 4), g = c1 - c0;
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * nrow;
    Row<V> acc[4];
    for (int q = 0; q < 4; ++q)
      for (int i = 0; i < V; ++i) acc[q].v[i] = _mm256_setzero_pd();
    if (g == 4) {
      const double *l1 = l0 + nrow, *l2 = l1 + nrow, *l3 = l2 + nrow;
      for (int r = c1; r < nrow; ++r) {
        const Row<V> a = load<V>(x + static_cast<std::ptrdiff_t>(r) * ld);
        add_scaled(acc[0], l0[r], a);
        add_scaled(acc[1], l1[r], a);
        add_scaled(acc[2], l2[r], a);
        add_scaled(acc[3], l3[r], a);
      }
    } else {
      for (int r = c1; r < nrow; ++r) {
        const Row<V> a = load<V>(x + static_cast<std::ptrdiff_t>(r) * ld);
        for (int q = 0; q < g; ++q) add_scaled(acc[q], l0[static_cast<std::ptrdiff_t>(q) * nrow + r], a);
      }
    }
    Row<V> solved[4] = {};
    for (int q = g - 1; q >= 0; --q) {
      const double* lc = l0 + static_cast<std::ptrdiff_t>(q) * nrow;
      double* xc = x + static_cast<std::ptrdiff_t>(c0 + q) * ld;
      for (int q2 = q + 1; q2 < g; ++q2) add_scaled(acc[q], lc[c0 + q2], solved[q2]);
      Row<V> v = load<V>(xc);
      for (int i = 0; i < V; ++i) v.v[i] = _mm256_sub_pd(v.v[i], acc[q].v[i]);
      divide(v, lc[c0 + q]);
      solved[q] = v;
      store(xc, v);
    }
  }
}

}  // namespace wide
const bool kWide = cpu_has_avx2_fma();
#endif

// The right-hand sides in chunks of 8 (the last one 4 wide where that is all that is left).
template <bool Forward>
void block_kernel(const Block& b, double* x, int mp, bool wide_kernels) {
  for (int j = 0; j < mp; j += 8) {
    const bool eight = mp - j >= 8;
#if defined(__x86_64__) && defined(__GNUC__)
    if (kWide && wide_kernels) {
      if constexpr (Forward)
        eight ? wide::forward<2>(b.l, b.nrow, b.ncol, x + j, mp) : wide::forward<1>(b.l, b.nrow, b.ncol, x + j, mp);
      else
        eight ? wide::backward<2>(b.l, b.nrow, b.ncol, x + j, mp) : wide::backward<1>(b.l, b.nrow, b.ncol, x + j, mp);
      continue;
    }
#endif
    if constexpr (Forward)
      eight ? forward<8>(b.l, b.nrow, b.ncol, x + j, mp) : forward<4>(b.l, b.nrow, b.ncol, x + j, mp);
    else
      eight ? backward<8>(b.l, b.nrow, b.ncol, x + j, mp) : backward<4>(b.l, b.nrow, b.ncol, x + j, mp);
  }
}


// Rows of y (row-major, mp doubles each) into the block's x and back.
void gather(const Block& b, const double* y, int mp, int rows, double* x) {
  for (int i = 0; i < rows; ++i)
    std::copy_n(y + static_cast<std::ptrdiff_t>(b.rows[i]) * mp, mp, x + static_cast<std::ptrdiff_t>(i) * mp);
}

void store_own_rows(const Block& b, const double* x, int mp, double* y) {
  std::copy_n(x, static_cast<std::ptrdiff_t>(b.ncol) * mp, y + static_cast<std::ptrdiff_t>(b.rows[0]) * mp);
}

// One supernode of the forward solve in y; its rows at or beyond `limit` are added to `above`
// instead, at their position in above_rows (the subtree root's rows below its own).
void forward_supernode(const Block& b, const Sweep& w, double* x, int limit, const int* above_rows, int n_above,
                       double* above, std::atomic<bool>& missing) {
  double* y = w.y;
  const int mp = w.mp;
  gather(b, y, mp, b.ncol, x);
  std::fill(x + static_cast<std::ptrdiff_t>(b.ncol) * mp, x + static_cast<std::ptrdiff_t>(b.nrow) * mp, 0.0);
  block_kernel<true>(b, x, mp, w.wide);
  store_own_rows(b, x, mp, y);
  for (int i = b.ncol; i < b.nrow; ++i) {
    const int row = b.rows[i];
    double* dst = y + static_cast<std::ptrdiff_t>(row) * mp;
    if (row >= limit) {
      const int* at = std::lower_bound(above_rows, above_rows + n_above, row);
      if (at == above_rows + n_above || *at != row) {
        missing = true;  // not the structure assumed: the caller solves otherwise
        continue;
      }
      dst = above + (at - above_rows) * mp;
    }
    const double* src = x + static_cast<std::ptrdiff_t>(i) * mp;
    for (int j = 0; j < mp; ++j) dst[j] += src[j];
  }
}

void backward_supernode(const Block& b, const Sweep& w, double* x) {
  gather(b, w.y, w.mp, b.nrow, x);
  block_kernel<false>(b, x, w.mp, w.wide);
  store_own_rows(b, x, w.mp, w.y);
}

}  // namespace

SupernodalSolve::SupernodalSolve(const SupernodalFactor& f) {
  const int ns = f.nsuper;
  if (f.n <= 0 || ns <= 0 || f.super[ns] != f.n) return;
  std::vector<int> col_super(static_cast<std::size_t>(f.n));
  for (int s = 0; s < ns; ++s)
    for (int c = f.super[s]; c < f.super[s + 1]; ++c) col_super[static_cast<std::size_t>(c)] = s;
  std::vector<int> parent(static_cast<std::size_t>(ns), -1), first(static_cast<std::size_t>(ns)),
      count(static_cast<std::size_t>(ns), 1);
  std::vector<double> cost(static_cast<std::size_t>(ns));
  std::vector<int> max_rows(static_cast<std::size_t>(ns));
  double total = 0.0;
  for (int s = 0; s < ns; ++s) {
    const Block b = block(f, s);
    if (b.ncol <= 0 || b.nrow < b.ncol) return;
    for (int i = 0; i < b.nrow; ++i) {
      const bool own = i < b.ncol;
      if (own ? b.rows[i] != f.super[s] + i : b.rows[i] <= b.rows[i - 1] || b.rows[i] >= f.n) return;
    }
    if (b.nrow > b.ncol) parent[static_cast<std::size_t>(s)] = col_super[static_cast<std::size_t>(b.rows[b.ncol])];
    first[static_cast<std::size_t>(s)] = s;
    cost[static_cast<std::size_t>(s)] = static_cast<double>(b.nrow) * b.ncol;
    max_rows[static_cast<std::size_t>(s)] = b.nrow;
    total += cost[static_cast<std::size_t>(s)];
  }
  std::vector<std::vector<int>> children(static_cast<std::size_t>(ns));
  for (int s = 0; s < ns; ++s) {  // parents come after their children
    const int p = parent[static_cast<std::size_t>(s)];
    if (p < 0) continue;
    const auto ps = static_cast<std::size_t>(p), ss = static_cast<std::size_t>(s);
    cost[ps] += cost[ss];
    count[ps] += count[ss];
    first[ps] = std::min(first[ps], first[ss]);
    max_rows[ps] = std::max(max_rows[ps], max_rows[ss]);
    children[ps].push_back(s);
  }
  // Split the costliest subtree into its children until each is at most kSubtreeShare.
  auto heavier = [&](int a, int b) { return cost[static_cast<std::size_t>(a)] < cost[static_cast<std::size_t>(b)]; };
  std::priority_queue<int, std::vector<int>, decltype(heavier)> open(heavier);
  for (int s = 0; s < ns; ++s)
    if (parent[static_cast<std::size_t>(s)] < 0) open.push(s);
  std::vector<int> roots;
  while (!open.empty()) {
    const int s = open.top();
    open.pop();
    const auto ss = static_cast<std::size_t>(s);
    if (cost[ss] <= kSubtreeShare * total || children[ss].empty()) {
      roots.push_back(s);
      continue;
    }
    top_.push_back(s);
    top_max_rows_ = std::max(top_max_rows_, block(f, s).nrow);
    for (int c : children[ss]) open.push(c);
  }
  std::sort(top_.begin(), top_.end());
  std::sort(roots.begin(), roots.end(), [&](int a, int b) { return heavier(b, a) || (!heavier(a, b) && a < b); });
  for (int r : roots) {
    const auto rs = static_cast<std::size_t>(r);
    if (count[rs] != r - first[rs] + 1) return;  // not postordered
    subtrees_.push_back({first[rs], r, f.super[first[rs]], f.super[r + 1], max_rows[rs]});
  }
  ok_ = true;
}

void SupernodalSolve::forward_subtree(const SupernodalFactor& f, const Subtree& t, const detail::SupernodalSweep& w, double* work,
                                      double* above, std::atomic<bool>& missing) const {
  const Block root = block(f, t.last);
  for (int s = t.first; s <= t.last; ++s)
    forward_supernode(block(f, s), w, work, t.col_end, root.rows + root.ncol, root.nrow - root.ncol, above, missing);
}

void SupernodalSolve::backward_subtree(const SupernodalFactor& f, const Subtree& t, const detail::SupernodalSweep& w,
                                       double* work) const {
  for (int s = t.last; s >= t.first; --s) backward_supernode(block(f, s), w, work);
}

std::optional<Eigen::MatrixXd> SupernodalSolve::solve(const SupernodalFactor& f, const Eigen::MatrixXd& b,
                                                      bool wide_kernels) const {
  const int n = f.n;
  const int cols = static_cast<int>(b.cols());
  const int m = (cols + 3) / 4 * 4;  // each row a whole number of 4-wide vectors
  // y: P b, row-major, so that a supernode gathers each of its rows from one place.
  std::vector<double> y(static_cast<std::size_t>(n) * static_cast<std::size_t>(m), 0.0);
  for (int k = 0; k < n; ++k) {
    const int row = f.perm ? f.perm[k] : k;
    for (int j = 0; j < cols; ++j) y[static_cast<std::size_t>(k) * m + j] = b(row, j);
  }
  // Per subtree: its workspace, then its contributions to the rows above it.
  std::vector<std::size_t> offset(subtrees_.size() + 1, 0);
  for (std::size_t i = 0; i < subtrees_.size(); ++i) {
    const Block root = block(f, subtrees_[i].last);
    offset[i + 1] = offset[i] + static_cast<std::size_t>(subtrees_[i].max_rows + root.nrow - root.ncol) * m;
  }
  std::vector<double> space(offset.back() + 1, 0.0);
  auto work_of = [&](std::size_t i) { return space.data() + offset[i]; };
  auto above_of = [&](std::size_t i) { return work_of(i) + static_cast<std::size_t>(subtrees_[i].max_rows) * m; };
  const auto count = static_cast<std::ptrdiff_t>(subtrees_.size());
  const Sweep sweep{y.data(), m, wide_kernels};
  std::atomic<bool> missing{false};
  parallel_for(count, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<std::size_t>(lo); i < static_cast<std::size_t>(hi); ++i)
      forward_subtree(f, subtrees_[i], sweep, work_of(i), above_of(i), missing);
  });
  if (missing) return std::nullopt;
  // The subtrees' contributions in a fixed order: the same sums on any number of threads.
  for (std::size_t i = 0; i < subtrees_.size(); ++i) {
    const Block root = block(f, subtrees_[i].last);
    const double* above = above_of(i);
    for (int r = 0; r < root.nrow - root.ncol; ++r)
      for (int j = 0; j < m; ++j)
        y[static_cast<std::size_t>(root.rows[root.ncol + r]) * m + j] += above[static_cast<std::size_t>(r) * m + j];
  }
  std::vector<double> work(static_cast<std::size_t>(top_max_rows_) * m);
  for (int s : top_) forward_supernode(block(f, s), sweep, work.data(), n, nullptr, 0, nullptr, missing);
  for (auto it = top_.rbegin(); it != top_.rend(); ++it) backward_supernode(block(f, *it), sweep, work.data());
  parallel_for(count, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<std::size_t>(lo); i < static_cast<std::size_t>(hi); ++i)
      backward_subtree(f, subtrees_[i], sweep, work_of(i));
  });
  Eigen::MatrixXd x(n, cols);
  for (int k = 0; k < n; ++k) {
    const int row = f.perm ? f.perm[k] : k;
    for (int j = 0; j < cols; ++j) x(row, j) = y[static_cast<std::size_t>(k) * m + j];
  }
  return x;
}

}  // namespace freeform
