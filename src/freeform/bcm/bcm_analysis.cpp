#include "freeform/bcm/bcm_analysis.h"
#include "freeform/bcm/patch.h"

#include "freeform/common/held_threads.h"
#include "freeform/common/parallel.h"
#include "freeform/common/phase_clock.h"
#include "freeform/mesh/traversal.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <exception>
#include <system_error>
#include <thread>
#include <vector>
#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace freeform {
namespace {

bool expect_symmetric(const BcmSettings& s) {
  if (s.order < 3) return true;
  auto even = [](double c) { return c == 0.0 || c == 2.0; };  // lambda_1(c) = lambda_2(c)
  if (!even(resolved_outer(s)) || !even(resolved_inner(s))) return false;
  return std::all_of(s.smoothness.segments.begin(), s.smoothness.segments.end(),
                     [&](const SmoothnessSegment& g) { return even(g.value); });
}

// Columns per block of the pattern's walk, at least: a block allocates a marker per local vertex.
constexpr int kMinBlockColumns = 8192;

// The adjacency among the free vertices and those within `rings` rings of them, in the patch's
// local indices (free ones 0 .. n-1, in `free`'s order).
struct LocalGraph {
  std::vector<int> offset, to;  // the neighbours of local vertex l: to[offset[l] .. offset[l + 1])
};

LocalGraph local_graph(const Mesh& mesh, const std::vector<Vertex>& free, int rings) {
  const Patch p = build_patch(mesh, free, rings);
  LocalGraph g;
  g.offset.reserve(p.order.size() + 1);
  g.offset.push_back(0);
  for (Vertex v : p.order) {
    for (Halfedge h : mesh.outgoing(v))
      if (const int l = p.local[mesh.to_vertex(h)]; l >= 0) g.to.push_back(l);
    g.offset.push_back(static_cast<int>(g.to.size()));
  }
  return g;
}

// Column j's rows below it: the free vertices within `order` rings of j, sorted. seen (one
// entry per local vertex) marks the vertices met for column j with j.
void walk_column(const LocalGraph& g, int n, int order, int j, std::vector<int>& seen, std::vector<int>& frontier,
                 std::vector<int>& next, std::vector<int>& column) {
  column.assign(1, j);
  frontier.assign(1, j);
  seen[static_cast<std::size_t>(j)] = j;
  for (int depth = 0; depth < order; ++depth) {
    next.clear();
    for (int u : frontier)
      for (int t = g.offset[static_cast<std::size_t>(u)]; t < g.offset[static_cast<std::size_t>(u) + 1]; ++t) {
        const int w = g.to[static_cast<std::size_t>(t)];
        if (seen[static_cast<std::size_t>(w)] == j) continue;
        seen[static_cast<std::size_t>(w)] = j;
        next.push_back(w);
        if (w > j && w < n) column.push_back(w);
      }
    frontier.swap(next);
  }
  std::sort(column.begin(), column.end());
}

}  // namespace

// A walk expands the vertices at depth 0 .. order-1, which lie within order-1 rings of the free
// set; deeper ones are never free, so the local graph leaves them out. The columns are walked in
// contiguous blocks, one per thread the budget leaves free (run_tasks), and written into the
// matrix's own arrays: the same matrix on any number of threads.
Eigen::SparseMatrix<double> bcm_lower_pattern(const Mesh& mesh, const Regions& regions, int order,
                                              const std::atomic<bool>* stop) {
  const std::vector<Vertex> free = breadth_first_order(mesh, regions.free_vertices());
  const int n = static_cast<int>(free.size());
  const LocalGraph g = local_graph(mesh, free, order - 1);
  const int blocks = std::clamp(n / kMinBlockColumns, 1, threads_free());
  const auto first = [&](int b) { return static_cast<int>(static_cast<std::int64_t>(n) * b / blocks); };
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(blocks));
  std::vector<int> outer(static_cast<std::size_t>(n) + 1, 0);  // column counts, then offsets
  std::atomic<bool> stopped{false};
  run_tasks(blocks, [&](int b) {
    std::vector<int> seen(g.offset.size() - 1, -1), column, frontier, next;
    std::vector<int>& inner = rows[static_cast<std::size_t>(b)];
    for (int j = first(b); j < first(b + 1); ++j) {
      if (stop && j % 4096 == 0 && stop->load(std::memory_order_relaxed)) {
        stopped = true;
        return;
      }
      walk_column(g, n, order, j, seen, frontier, next, column);
      inner.insert(inner.end(), column.begin(), column.end());
      outer[static_cast<std::size_t>(j) + 1] = static_cast<int>(column.size());
    }
  });
  if (stopped) return {};
  for (int j = 0; j < n; ++j) outer[static_cast<std::size_t>(j) + 1] += outer[static_cast<std::size_t>(j)];
  Eigen::SparseMatrix<double> lower(n, n);
  lower.resizeNonZeros(outer.back());
  std::copy(outer.begin(), outer.end(), lower.outerIndexPtr());
  run_tasks(blocks, [&](int b) {
    const std::vector<int>& inner = rows[static_cast<std::size_t>(b)];
    const int at = outer[static_cast<std::size_t>(first(b))];
    std::copy(inner.begin(), inner.end(), lower.innerIndexPtr() + at);
    std::fill_n(lower.valuePtr() + at, inner.size(), 0.0);
  });
  return lower;
}

struct BcmAnalysis::Shared {
  std::atomic<bool> abandoned{false};
  std::promise<void> read_done;
  std::promise<std::unique_ptr<CholeskyAnalysis>> result;
  std::atomic<double> ms{0.0}, cpu_ms{0.0};
};

BcmAnalysis::BcmAnalysis(const Mesh& mesh, const Regions& regions, const BcmSettings& settings, int min_free,
                         std::function<void()> before_ordering) {
  if (regions.n_free() < min_free || !expect_symmetric(settings)) return;
  if (settings.solver != SolverKind::Auto && settings.solver != SolverKind::CholmodSupernodal) return;
  // No core beside the caller's and the analyses already ahead (FREEFORM_THREADS=1; on 2 cores
  // the operator shape's fill beside the system's): the solver analyzes A itself.
  if (threads_free() < 2) return;
  // Held from here, not from when the thread first runs: an analysis started right after this
  // one must see it. Released before the result is handed over.
  auto held = std::make_unique<HeldThread>();
  shared_ = std::make_shared<Shared>();
  read_done_ = shared_->read_done.get_future();
  future_ = shared_->result.get_future();
  try {
    std::thread([&mesh, &regions, k = settings.order, shared = shared_, hook = std::move(before_ordering),
                 held = std::move(held)]() mutable {
      const auto t = std::chrono::steady_clock::now();
      const double cpu0 = PhaseClock::thread_cpu_ms() + helper_cpu_ms();
      Eigen::SparseMatrix<double> lower = [&] {
        try {
          return bcm_lower_pattern(mesh, regions, k, &shared->abandoned);
        } catch (const std::exception&) {  // e.g. out of memory: the solver analyzes A itself and reports
          return Eigen::SparseMatrix<double>();
        }
      }();
      shared->read_done.set_value();  // mesh and regions may be gone from here on
      if (hook) hook();
      std::unique_ptr<CholeskyAnalysis> out;
      try {
        if (lower.rows() > 0 && !shared->abandoned) out = std::make_unique<CholeskyAnalysis>(lower);
        if (out && !out->ok()) out.reset();
      } catch (const std::exception&) {
        out.reset();
      }
      Eigen::SparseMatrix<double>().swap(lower);  // before the result: the caller's peak follows
      shared->ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
      shared->cpu_ms = PhaseClock::thread_cpu_ms() + helper_cpu_ms() - cpu0;
      held.reset();
      shared->result.set_value(std::move(out));
    }).detach();
  } catch (const std::system_error&) {  // no thread to be had: the solver analyzes A itself
    shared_.reset();
    return;
  }
  started_ = true;
}

BcmAnalysis::~BcmAnalysis() {
  if (!shared_) return;
  shared_->abandoned = true;
  read_done_.wait();
}

double BcmAnalysis::ms() const { return shared_ ? shared_->ms.load() : 0.0; }
double BcmAnalysis::cpu_ms() const { return shared_ ? shared_->cpu_ms.load() : 0.0; }

CholeskyAnalysis* BcmAnalysis::get() {
  if (future_.valid()) {
    result_ = future_.get();
#ifdef __GLIBC__
    // The thread's own malloc arena keeps METIS's freed workspace resident; hand it back
    // before the numeric factorization reaches the process's peak (+90 MB at 1M free without).
    malloc_trim(0);
#endif
  }
  return result_.get();
}

}  // namespace freeform
