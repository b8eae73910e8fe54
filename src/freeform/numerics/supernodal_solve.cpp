#include "freeform/numerics/supernodal_solve.h"

#include "freeform/common/cpu_features.h"
#include "freeform/common/parallel.h"
#include "freeform/numerics/csr.h"

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
  bool top;  // the supernodes above the subtrees: alone on the pool
};

namespace {

using Sweep = detail::SupernodalSweep;

// Subtrees are split until none holds more than this share of the factor: enough for 16 cores
// to balance, and the top of the tree they leave (the solve's serial part) stays a few percent.
constexpr double kSubtreeShare = 1.0 / 64.0;
// Rows per chunk of the permuted gather and scatter around the sweeps.
constexpr std::ptrdiff_t kCopyGrain = 4096;

struct Block {
  int ncol, nrow;
  const int* rows;
  const double* l;  // nrow by ncol, column-major
};

Block block(const SupernodalFactor& f, int s) {
  return {f.super[s + 1] - f.super[s], f.pi[s + 1] - f.pi[s], f.s_rows + f.pi[s], f.x + f.px[s]};
}

template <int W>
void update(const double* l, int ldl, int ncol, int lo, int hi, const double* xs, double* x, int ld) {
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * ldl;
    const double* p = xs + static_cast<std::ptrdiff_t>(c0) * ld;
    if (g == 4) {
      const double *l1 = l0 + ldl, *l2 = l1 + ldl, *l3 = l2 + ldl;
      double p0[W], p1[W], p2[W], p3[W];
      for (int k = 0; k < W; ++k) p0[k] = p[k], p1[k] = p[ld + k], p2[k] = p[2 * ld + k], p3[k] = p[3 * ld + k];
      for (int r = lo; r < hi; ++r) {
        double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
        const double a0 = l0[r], a1 = l1[r], a2 = l2[r], a3 = l3[r];
        for (int k = 0; k < W; ++k) xr[k] -= a0 * p0[k] + a1 * p1[k] + a2 * p2[k] + a3 * p3[k];
      }
      continue;
    }
    for (int r = lo; r < hi; ++r) {
      double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
      for (int q = 0; q < g; ++q) {
        const double a = l0[static_cast<std::ptrdiff_t>(q) * ldl + r];
        for (int k = 0; k < W; ++k) xr[k] -= a * p[static_cast<std::ptrdiff_t>(q) * ld + k];
      }
    }
  }
}

template <int W>
void accumulate(const double* l, int ldl, int ncol, int lo, int hi, const double* x, int ld, double* acc) {
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * ldl;
    double* a = acc + static_cast<std::ptrdiff_t>(c0) * W;
    if (g == 4) {
      const double *l1 = l0 + ldl, *l2 = l1 + ldl, *l3 = l2 + ldl;
      double s0[W], s1[W], s2[W], s3[W];
      for (int k = 0; k < W; ++k) s0[k] = a[k], s1[k] = a[W + k], s2[k] = a[2 * W + k], s3[k] = a[3 * W + k];
      for (int r = lo; r < hi; ++r) {
        const double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
        const double a0 = l0[r], a1 = l1[r], a2 = l2[r], a3 = l3[r];
        for (int k = 0; k < W; ++k) {
          s0[k] += a0 * xr[k];
          s1[k] += a1 * xr[k];
          s2[k] += a2 * xr[k];
          s3[k] += a3 * xr[k];
        }
      }
      for (int k = 0; k < W; ++k) a[k] = s0[k], a[W + k] = s1[k], a[2 * W + k] = s2[k], a[3 * W + k] = s3[k];
      continue;
    }
    for (int r = lo; r < hi; ++r) {
      const double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
      for (int q = 0; q < g; ++q) {
        const double v = l0[static_cast<std::ptrdiff_t>(q) * ldl + r];
        for (int k = 0; k < W; ++k) a[q * W + k] += v * xr[k];
      }
    }
  }
}

// The triangle of columns [c0, c0 + g) (g <= 4) and its rows: forward substitution, and backward
// with acc (g rows of W) the sums from the rows below.
template <int W>
void forward_group(const double* l, int ldl, int c0, int g, double* x, int ld) {
  for (int q = 0; q < g; ++q) {
    const double* lc = l + static_cast<std::ptrdiff_t>(c0 + q) * ldl;
    double* xc = x + static_cast<std::ptrdiff_t>(c0 + q) * ld;
    for (int q0 = 0; q0 < q; ++q0) {
      const double v = l[static_cast<std::ptrdiff_t>(c0 + q0) * ldl + c0 + q];
      const double* p = x + static_cast<std::ptrdiff_t>(c0 + q0) * ld;
      for (int k = 0; k < W; ++k) xc[k] -= v * p[k];
    }
    for (int k = 0; k < W; ++k) xc[k] /= lc[c0 + q];
  }
}

template <int W>
void backward_group(const double* l, int ldl, int c0, int g, double* x, int ld, double* acc) {
  for (int q = g - 1; q >= 0; --q) {
    const double* lc = l + static_cast<std::ptrdiff_t>(c0 + q) * ldl;
    double* xc = x + static_cast<std::ptrdiff_t>(c0 + q) * ld;
    for (int q2 = q + 1; q2 < g; ++q2) {
      const double* xr = x + static_cast<std::ptrdiff_t>(c0 + q2) * ld;
      for (int k = 0; k < W; ++k) acc[q * W + k] += lc[c0 + q2] * xr[k];
    }
    for (int k = 0; k < W; ++k) xc[k] = (xc[k] - acc[q * W + k]) / lc[c0 + q];
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
[[gnu::target("avx2,fma")]] void update(const double* l, int ldl, int ncol, int lo, int hi, const double* xs, double* x,
                                        int ld) {
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * ldl;
    Row<V> p[4] = {};
    for (int q = 0; q < g; ++q) p[q] = load<V>(xs + static_cast<std::ptrdiff_t>(c0 + q) * ld);
    if (g == 4) {
      const double *l1 = l0 + ldl, *l2 = l1 + ldl, *l3 = l2 + ldl;
      for (int r = lo; r < hi; ++r) {
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
    for (int r = lo; r < hi; ++r) {
      double* xr = x + static_cast<std::ptrdiff_t>(r) * ld;
      Row<V> a = load<V>(xr);
      for (int q = 0; q < g; ++q) sub_scaled(a, l0[static_cast<std::ptrdiff_t>(q) * ldl + r], p[q]);
      store(xr, a);
    }
  }
}

template <int V>
[[gnu::target("avx2,fma")]] void accumulate(const double* l, int ldl, int ncol, int lo, int hi, const double* x, int ld,
                                            double* acc) {
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    const double* l0 = l + static_cast<std::ptrdiff_t>(c0) * ldl;
    Row<V> s[4] = {};
    for (int q = 0; q < g; ++q) s[q] = load<V>(acc + static_cast<std::ptrdiff_t>(c0 + q) * 4 * V);
    if (g == 4) {
      const double *l1 = l0 + ldl, *l2 = l1 + ldl, *l3 = l2 + ldl;
      for (int r = lo; r < hi; ++r) {
        const Row<V> a = load<V>(x + static_cast<std::ptrdiff_t>(r) * ld);
        add_scaled(s[0], l0[r], a);
        add_scaled(s[1], l1[r], a);
        add_scaled(s[2], l2[r], a);
        add_scaled(s[3], l3[r], a);
      }
    } else {
      for (int r = lo; r < hi; ++r) {
        const Row<V> a = load<V>(x + static_cast<std::ptrdiff_t>(r) * ld);
        for (int q = 0; q < g; ++q) add_scaled(s[q], l0[static_cast<std::ptrdiff_t>(q) * ldl + r], a);
      }
    }
    for (int q = 0; q < g; ++q) store(acc + static_cast<std::ptrdiff_t>(c0 + q) * 4 * V, s[q]);
  }
}

}  // namespace wide
const bool kWide = cpu_has_avx2_fma();
#endif

// The kernels for chunks of W right-hand sides, picked once per chunk.
template <int W>
struct Kernels {
  void (*update)(const double*, int, int, int, int, const double*, double*, int);
  void (*accumulate)(const double*, int, int, int, int, const double*, int, double*);
};

template <int W>
Kernels<W> kernels(bool wide_kernels) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (kWide && wide_kernels) return {wide::update<W / 4>, wide::accumulate<W / 4>};
#endif
  (void)wide_kernels;
  return {update<W>, accumulate<W>};
}

// One supernode's dense part, or the rows [lo, hi) of it (the others run concurrently): x is
// its rows by W right-hand sides, row-major with leading dimension ld. forward: on entry the
// first ncol rows hold the right-hand side and the others 0; on exit the first ncol rows hold
// L11^-1 of it and the others -L21 times that. backward: on entry the own rows hold the
// right-hand side and the others the solution; on exit the own rows hold L11^-T (rhs - L21^T
// others). Columns go four at a time, so that each row below is loaded once per four columns
// of the factor: the solve is bound by reading the factor, not by flops.
template <int W>
void forward_chunk(const double* l, int ldl, int nrow, int ncol, double* x, int ld, bool wide_kernels) {
  const Kernels<W> k = kernels<W>(wide_kernels);
  for (int c0 = 0; c0 < ncol; c0 += 4) {
    const int g = std::min(4, ncol - c0);
    forward_group<W>(l, ldl, c0, g, x, ld);
    k.update(l + static_cast<std::ptrdiff_t>(c0) * ldl, ldl, g, c0 + g, nrow, x + static_cast<std::ptrdiff_t>(c0) * ld,
             x, ld);
  }
}

template <int W>
void backward_chunk(const double* l, int ldl, int nrow, int ncol, double* x, int ld, bool wide_kernels) {
  const Kernels<W> k = kernels<W>(wide_kernels);
  for (int c1 = ncol; c1 > 0; c1 -= 4) {
    const int c0 = std::max(0, c1 - 4), g = c1 - c0;
    double acc[4 * W] = {};
    k.accumulate(l + static_cast<std::ptrdiff_t>(c0) * ldl, ldl, g, c1, nrow, x, ld, acc);
    backward_group<W>(l, ldl, c0, g, x, ld, acc);
  }
}

// A supernode at the top of the tree, where no subtrees are left to run beside it: panels of
// kPanel columns, each panel's triangle on one thread and the rows below it in blocks of
// kRowBlock on the pool. The blocks are fixed and their sums added in order: the same bits on any
// number of threads.
constexpr int kPanel = 64;
constexpr int kRowBlock = 128;

template <int W>
void forward_panels(const double* l, int nrow, int ncol, double* x, int ld, bool wide_kernels) {
  const Kernels<W> k = kernels<W>(wide_kernels);
  for (int c0 = 0; c0 < ncol; c0 += kPanel) {
    const int pc = std::min(kPanel, ncol - c0);
    const double* lp = l + static_cast<std::ptrdiff_t>(c0) * nrow;
    double* xp = x + static_cast<std::ptrdiff_t>(c0) * ld;
    forward_chunk<W>(lp + c0, nrow, pc, pc, xp, ld, wide_kernels);
    const int first = c0 + pc, blocks = (nrow - first + kRowBlock - 1) / kRowBlock;
    parallel_for(blocks, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
      for (auto i = static_cast<int>(lo); i < hi; ++i)
        k.update(lp, nrow, pc, first + i * kRowBlock, std::min(nrow, first + (i + 1) * kRowBlock), xp, x, ld);
    });
  }
}

template <int W>
void backward_panels(const double* l, int nrow, int ncol, double* x, int ld, bool wide_kernels) {
  const Kernels<W> k = kernels<W>(wide_kernels);
  std::vector<double> partial;
  for (int c1 = ncol; c1 > 0; c1 -= kPanel) {
    const int c0 = std::max(0, c1 - kPanel), pc = c1 - c0;
    const double* lp = l + static_cast<std::ptrdiff_t>(c0) * nrow;
    double* xp = x + static_cast<std::ptrdiff_t>(c0) * ld;
    const int blocks = (nrow - c1 + kRowBlock - 1) / kRowBlock;
    const std::size_t stride = static_cast<std::size_t>(pc) * W;
    partial.assign(static_cast<std::size_t>(blocks) * stride, 0.0);
    parallel_for(blocks, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
      for (auto i = static_cast<int>(lo); i < hi; ++i)
        k.accumulate(lp, nrow, pc, c1 + i * kRowBlock, std::min(nrow, c1 + (i + 1) * kRowBlock), x, ld,
                     partial.data() + static_cast<std::size_t>(i) * stride);
    });
    for (int i = 0; i < blocks; ++i)
      for (int q = 0; q < pc; ++q)
        for (int j = 0; j < W; ++j)
          xp[static_cast<std::ptrdiff_t>(q) * ld + j] -= partial[static_cast<std::size_t>(i) * stride + q * W + j];
    backward_chunk<W>(lp + c0, nrow, pc, pc, xp, ld, wide_kernels);
  }
}

// One chunk of W right-hand sides through a supernode. panels: a top supernode large enough to
// split its rows among the pool's threads.
template <bool Forward, int W>
void chunk_kernel(const Block& b, double* x, int mp, bool wide_kernels, bool panels) {
  if constexpr (Forward)
    panels ? forward_panels<W>(b.l, b.nrow, b.ncol, x, mp, wide_kernels)
           : forward_chunk<W>(b.l, b.nrow, b.nrow, b.ncol, x, mp, wide_kernels);
  else
    panels ? backward_panels<W>(b.l, b.nrow, b.ncol, x, mp, wide_kernels)
           : backward_chunk<W>(b.l, b.nrow, b.nrow, b.ncol, x, mp, wide_kernels);
}

// The right-hand sides in chunks of 8 (the last one 4 wide where that is all that is left).
template <bool Forward>
void block_kernel(const Block& b, double* x, int mp, bool wide_kernels, bool panels) {
  for (int j = 0; j < mp; j += 8)
    mp - j >= 8 ? chunk_kernel<Forward, 8>(b, x + j, mp, wide_kernels, panels)
                : chunk_kernel<Forward, 4>(b, x + j, mp, wide_kernels, panels);
}

// Top supernodes with at least this many rows below a panel go by panels.
constexpr int kPanelRows = 2 * kRowBlock;

// What a top supernode solves on one thread: all of it, or by panels their triangles.
double serial_entries(const Block& b) {
  if (b.nrow < kPanelRows) return static_cast<double>(b.nrow) * b.ncol;
  double triangles = 0.0;
  for (int c0 = 0; c0 < b.ncol; c0 += kPanel) {
    const double pc = std::min(kPanel, b.ncol - c0);
    triangles += pc * (pc + 1) / 2;
  }
  return triangles;
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
  block_kernel<true>(b, x, mp, w.wide, w.top && b.nrow >= kPanelRows);
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
  block_kernel<false>(b, x, w.mp, w.wide, w.top && b.nrow >= kPanelRows);
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
    serial_share_ += serial_entries(block(f, s)) / total;
    for (int c : children[ss]) open.push(c);
  }
  std::sort(top_.begin(), top_.end());
  std::sort(roots.begin(), roots.end(), [&](int a, int b) { return heavier(b, a) || (!heavier(a, b) && a < b); });
  for (int r : roots) {
    const auto rs = static_cast<std::size_t>(r);
    if (count[rs] != r - first[rs] + 1) return;  // not postordered
    subtrees_.push_back({first[rs], r, f.super[r + 1], max_rows[rs]});
  }
  ok_ = true;
}

void SupernodalSolve::forward_subtree(const SupernodalFactor& f, const Subtree& t, const detail::SupernodalSweep& w,
                                      double* work, double* above, std::atomic<bool>& missing) const {
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
  // y: P b, row-major, so that a supernode gathers each of its rows from one place; gathered
  // (and first touched) on the pool, as x is scattered below.
  std::vector<double, UninitializedAllocator<double>> y(static_cast<std::size_t>(n) * static_cast<std::size_t>(m));
  parallel_for(n, kCopyGrain, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto k = static_cast<int>(lo); k < hi; ++k) {
      const int row = f.perm ? f.perm[k] : k;
      double* yk = y.data() + static_cast<std::size_t>(k) * m;
      for (int j = 0; j < cols; ++j) yk[j] = b(row, j);
      std::fill(yk + cols, yk + m, 0.0);
    }
  });
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
  const Sweep sweep{y.data(), m, wide_kernels, false};
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
  const Sweep top{y.data(), m, wide_kernels, true};
  for (int s : top_) forward_supernode(block(f, s), top, work.data(), n, nullptr, 0, nullptr, missing);
  for (auto it = top_.rbegin(); it != top_.rend(); ++it) backward_supernode(block(f, *it), top, work.data());
  parallel_for(count, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<std::size_t>(lo); i < static_cast<std::size_t>(hi); ++i)
      backward_subtree(f, subtrees_[i], sweep, work_of(i));
  });
  Eigen::MatrixXd x(n, cols);
  parallel_for(n, kCopyGrain, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto k = static_cast<int>(lo); k < hi; ++k) {
      const int row = f.perm ? f.perm[k] : k;
      for (int j = 0; j < cols; ++j) x(row, j) = y[static_cast<std::size_t>(k) * m + j];
    }
  });
  return x;
}

}  // namespace freeform
