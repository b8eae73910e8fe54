#include "freeform/numerics/supernodal_factorization.h"

#include "freeform/common/held_threads.h"
#include "freeform/common/parallel.h"

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <memory>
#include <utility>
#include <vector>

// The reference BLAS and LAPACK interface, as CHOLMOD calls it (no hidden string lengths).
extern "C" {
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha, const double* a,
            const int* lda, const double* beta, double* c, const int* ldc);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
}

namespace freeform {
namespace {

constexpr int kNone = -1;
// A supernode above the subtrees is updated in blocks of columns, one thread each: at least
// kColumnBlock columns (a BLAS call on fewer is slow), at most kColumnBlocks blocks. The blocks
// depend on the supernode alone, so each update is the same BLAS call on any number of threads.
constexpr int kColumnBlock = 64;
constexpr int kColumnBlocks = 32;

// Supernodes whose descendants still have rows to update them with: CHOLMOD's linked lists.
// pos[d] is the position (in the row list) of d's first row not yet used for an update.
struct Links {
  std::vector<int> head, next, pos;
  explicit Links(int nsuper) : head(static_cast<std::size_t>(nsuper), kNone), next(head), pos(head) {}
  void push(int d, int s) {
    next[static_cast<std::size_t>(d)] = head[static_cast<std::size_t>(s)];
    head[static_cast<std::size_t>(s)] = d;
  }
  std::vector<int> list(int s) const {
    std::vector<int> ds;
    for (int d = head[static_cast<std::size_t>(s)]; d != kNone; d = next[static_cast<std::size_t>(d)]) ds.push_back(d);
    return ds;
  }
};

class Factorization {
 public:
  Factorization(const SupernodalFactor& f, double* x, const TriangleCsc& a, double shift)
      : f_(f), x_(x), a_(a), shift_(shift), links_(f.nsuper), col_super_(static_cast<std::size_t>(f.n)) {
    for (int s = 0; s < f.nsuper; ++s)
      std::fill(col_super_.begin() + f.super[s], col_super_.begin() + f.super[s + 1], s);
  }

  int run(const SupernodalSolve& schedule);

 private:
  struct Scratch {
    std::vector<int> rel;
    std::vector<double> c;
  };
  int ncol(int s) const { return f_.super[s + 1] - f_.super[s]; }
  int nrow(int s) const { return f_.pi[s + 1] - f_.pi[s]; }
  double* block(int s) const { return x_ + f_.px[s]; }
  void prepare(int s, int* map) const;
  void load(int s, int c0, int c1, const int* map) const;
  void update(int d, int s, int c0, int c1, const int* map, Scratch& w) const;
  int factor_block(int s) const;
  // d's next supernode to update after s, kNone when it has none; moves d's position past s.
  int advance(int d, int s);
  int subtree(const SupernodalSolve::Subtree& t, std::vector<std::pair<int, int>>& exits);
  int top_supernode(int s, int* map);

  const SupernodalFactor& f_;
  double* x_;
  const TriangleCsc& a_;
  double shift_;
  Links links_;
  std::vector<int> col_super_;
  int blas_threads_ = 1;  // OpenBLAS's own count when the factorization began
};

// map[row] = the row's position in s.
void Factorization::prepare(int s, int* map) const {
  const int* rows = f_.s_rows + f_.pi[s];
  for (int i = 0; i < nrow(s); ++i) map[rows[i]] = i;
}

// s's columns [c0, c1) zeroed, then A's entries in them scattered through map.
void Factorization::load(int s, int c0, int c1, const int* map) const {
  const int k1 = f_.super[s], nr = nrow(s);
  double* xs = block(s);
  std::fill(xs + static_cast<std::ptrdiff_t>(c0) * nr, xs + static_cast<std::ptrdiff_t>(c1) * nr, 0.0);
  for (int j = k1 + c0; j < k1 + c1; ++j) {
    double* col = xs + static_cast<std::ptrdiff_t>(j - k1) * nr;
    for (int t = a_.outer[static_cast<std::size_t>(j)]; t < a_.outer[static_cast<std::size_t>(j) + 1]; ++t) {
      const int i = a_.inner[static_cast<std::size_t>(t)];
      if (i >= j) col[map[i]] += a_.value[static_cast<std::size_t>(t)] + (i == j ? shift_ : 0.0);
    }
  }
}

// s's columns [c0, c1) less d's update: C = L_d(r, :) L_d(r1, :)' for d's rows r from the first
// in those columns on, r1 the ones in them; scattered into s through map.
void Factorization::update(int d, int s, int c0, int c1, const int* map, Scratch& w) const {
  const int k1 = f_.super[s];
  const int* rows = f_.s_rows;
  const int from = links_.pos[static_cast<std::size_t>(d)], end = f_.pi[d + 1];
  const int pa = static_cast<int>(std::lower_bound(rows + from, rows + end, k1 + c0) - rows);
  const int pb = static_cast<int>(std::lower_bound(rows + pa, rows + end, k1 + c1) - rows);
  const int n1 = pb - pa, n2 = end - pa, n3 = n2 - n1;
  if (n1 == 0) return;
  const int k = ncol(d), ldd = nrow(d);
  const double* ld = block(d) + (pa - f_.pi[d]);
  w.c.resize(static_cast<std::size_t>(n2) * static_cast<std::size_t>(n1));
  const double one = 1.0, zero = 0.0;
  dsyrk_("L", "N", &n1, &k, &one, ld, &ldd, &zero, w.c.data(), &n2);
  if (n3 > 0) dgemm_("N", "T", &n3, &n1, &k, &one, ld + n1, &ldd, ld, &ldd, &zero, w.c.data() + n1, &n2);
  w.rel.resize(static_cast<std::size_t>(n2));
  for (int i = 0; i < n2; ++i) w.rel[static_cast<std::size_t>(i)] = map[rows[pa + i]];
  const int nr = nrow(s);
  double* xs = block(s);
  for (int j = 0; j < n1; ++j) {
    double* col = xs + static_cast<std::ptrdiff_t>(w.rel[static_cast<std::size_t>(j)]) * nr;
    const double* cj = w.c.data() + static_cast<std::ptrdiff_t>(j) * n2;
    for (int i = j; i < n2; ++i) col[w.rel[static_cast<std::size_t>(i)]] -= cj[i];
  }
}

// potrf of the diagonal block, trsm of the rows below it; the failing column, or kNone.
int Factorization::factor_block(int s) const {
  const int nc = ncol(s), nr = nrow(s);
  double* xs = block(s);
  int info = 0;
  dpotrf_("L", &nc, xs, &nr, &info);
  if (info != 0) return f_.super[s] + std::max(info, 1) - 1;
  const int below = nr - nc;
  const double one = 1.0;
  if (below > 0) dtrsm_("R", "L", "T", "N", &below, &nc, &one, xs, &nr, xs + nc, &nr);
  return kNone;
}

int Factorization::advance(int d, int s) {
  const int* rows = f_.s_rows;
  const int end = f_.pi[d + 1];
  int& pos = links_.pos[static_cast<std::size_t>(d)];
  pos =
      static_cast<int>(std::lower_bound(rows + std::max(pos, f_.pi[d] + ncol(d)), rows + end, f_.super[s + 1]) - rows);
  return pos < end ? col_super_[static_cast<std::size_t>(rows[pos])] : kNone;
}

// One subtree on this thread; links that leave it are kept in `exits` for the top. The failing
// column, or kNone.
int Factorization::subtree(const SupernodalSolve::Subtree& t, std::vector<std::pair<int, int>>& exits) {
  const std::unique_ptr<int[]> map(new int[static_cast<std::size_t>(f_.n)]);
  Scratch w;
  const auto link = [&](int d, int target) {
    if (target == kNone) return;
    if (target <= t.last)
      links_.push(d, target);
    else
      exits.emplace_back(d, target);
  };
  for (int s = t.first; s <= t.last; ++s) {
    prepare(s, map.get());
    load(s, 0, ncol(s), map.get());
    const std::vector<int> ds = links_.list(s);
    for (int d : ds) update(d, s, 0, ncol(s), map.get(), w);
    for (int d : ds) link(d, advance(d, s));
    if (const int bad = factor_block(s); bad != kNone) return bad;
    link(s, advance(s, s));
  }
  return kNone;
}

// A supernode above the subtrees: its columns' updates in fixed blocks on the pool (each
// column's in list order), potrf and trsm with OpenBLAS's own threads.
int Factorization::top_supernode(int s, int* map) {
  prepare(s, map);
  const std::vector<int> ds = links_.list(s);
  const int nc = ncol(s);
  const int width = std::max(kColumnBlock, (nc + kColumnBlocks - 1) / kColumnBlocks);
  parallel_for((nc + width - 1) / width, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    Scratch w;
    for (auto b = lo; b < hi; ++b) {
      const int c0 = static_cast<int>(b) * width, c1 = std::min(nc, c0 + width);
      load(s, c0, c1, map);
      for (int d : ds) update(d, s, c0, c1, map, w);
    }
  });
  for (int d : ds)
    if (const int next = advance(d, s); next != kNone) links_.push(d, next);
  int bad = kNone;
  {
    const BlasThreads all(blas_threads_);
    bad = factor_block(s);
  }
  if (bad != kNone) return bad;
  if (const int next = advance(s, s); next != kNone) links_.push(s, next);
  return kNone;
}

int Factorization::run(const SupernodalSolve& schedule) {
  // The BLAS on one thread while the pool calls it from several, then for the top's potrf and
  // trsm with the threads OpenBLAS already has (never more: a new one would need a buffer that
  // memory_limit.h did not count), at most those the budget leaves free (held_threads.h). The
  // pool's threads, not new ones, call it: OpenBLAS keeps a work buffer per calling thread, and
  // under an address-space limit a new thread's buffer can fail, which OpenBLAS retries forever.
  blas_threads_ = std::clamp(blas_threads(), 1, threads_free());
  const BlasThreads one(1);
  const int parts = schedule.subtrees();
  std::vector<std::vector<std::pair<int, int>>> exits(static_cast<std::size_t>(parts));
  std::atomic<int> minor{f_.n};
  parallel_for(parts, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<int>(lo); i < hi && minor.load() == f_.n; ++i) {
      const int bad = subtree(schedule.subtree(i), exits[static_cast<std::size_t>(i)]);
      if (bad != kNone)
        for (int m = minor.load(); bad < m && !minor.compare_exchange_weak(m, bad);) {
        }
    }
  });
  if (minor.load() < f_.n) return minor.load();
  for (const auto& part : exits)  // in the schedule's order: the same lists on any thread count
    for (const auto& [d, target] : part) links_.push(d, target);
  const std::unique_ptr<int[]> map(new int[static_cast<std::size_t>(f_.n)]);
  for (int s : schedule.top_supernodes())
    if (const int bad = top_supernode(s, map.get()); bad != kNone) return bad;
  return f_.n;
}

}  // namespace

int supernodal_factorize(const SupernodalFactor& layout, double* x, const SupernodalSolve& schedule,
                         const TriangleCsc& a, double shift) {
  return Factorization(layout, x, a, shift).run(schedule);
}

}  // namespace freeform
