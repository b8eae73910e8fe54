#include "freeform/numerics/nested_dissection.h"

#include "freeform/common/parallel.h"
#include "freeform/common/phase_clock.h"
#include "freeform/numerics/coarse_separator.h"

#if FREEFORM_HAVE_SUITESPARSE
#include "freeform/numerics/cholmod_view.h"
#include "freeform/numerics/supernodal_analysis.h"
#endif

#include <algorithm>
#include <cstddef>
#include <memory>

namespace freeform {

int dissection_parts(int threads) {
  int parts = 1;
  while (parts < threads && parts < 64) parts *= 2;
  return parts;
}

#if FREEFORM_HAVE_SUITESPARSE
namespace {

// Parts below this size are not split further: METIS orders them whole.
constexpr std::size_t kMinSplit = 2000;

// A node of the dissection tree: its vertices (global rows, ascending) until it is split, then
// its two children and its separator.
struct Node {
  std::vector<int> vertices;
  std::unique_ptr<Node> left, right;
  std::vector<int> separator;
  std::vector<int> order;  // a leaf's vertices in METIS's order
};

struct Common {
  cholmod_common c{};
  Common() {
    cholmod_start(&c);
    c.print = 0;
  }
  ~Common() { cholmod_finish(&c); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
};

// The lower-triangular pattern of `lower` restricted to `vertices` (ascending), in local rows.
struct SubPattern {
  std::vector<int> p, i;
  cholmod_sparse view{};
};

void extract(const Eigen::SparseMatrix<double>& lower, const std::vector<int>& vertices,
             const std::vector<int>& label, const std::vector<int>& local, SubPattern& out) {
  const int me = label[static_cast<std::size_t>(vertices.front())];
  out.p.assign(1, 0);
  out.i.clear();
  for (int j : vertices) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(lower, j); it; ++it) {
      const auto r = static_cast<std::size_t>(it.index());
      if (label[r] == me) out.i.push_back(local[r]);
    }
    out.p.push_back(static_cast<int>(out.i.size()));
  }
  out.view = cholmod_lower_view(vertices.size(), out.i.size(), out.p.data(), out.i.data());
}

// Labels the nodes' vertices (label = node index, local = position in its node; -1 for the
// separators above them) so that the concurrent tasks can extract their own subgraph from the
// shared pattern.
void label_nodes(const std::vector<Node*>& nodes, std::vector<int>& label, std::vector<int>& local) {
  std::fill(label.begin(), label.end(), -1);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const std::vector<int>& vs = nodes[n]->vertices;
    for (std::size_t k = 0; k < vs.size(); ++k) {
      label[static_cast<std::size_t>(vs[k])] = static_cast<int>(n);
      local[static_cast<std::size_t>(vs[k])] = static_cast<int>(k);
    }
  }
}

// Splits node by a METIS vertex separator; leaves it whole if METIS fails or a side is empty.
void split(const Eigen::SparseMatrix<double>& lower, Node& node, const std::vector<int>& label,
           const std::vector<int>& local) {
  SubPattern sub;
  extract(lower, node.vertices, label, local, sub);
  std::vector<int> partition(node.vertices.size());
  Common common;
  const SuiteSparse_long separator = cholmod_bisect(&sub.view, nullptr, 0, 1, partition.data(), &common.c);
  if (separator < 0 || common.c.status < CHOLMOD_OK) return;
  auto left = std::make_unique<Node>(), right = std::make_unique<Node>();
  std::vector<int> sep;
  for (std::size_t k = 0; k < partition.size(); ++k)
    (partition[k] == 0 ? left->vertices : partition[k] == 1 ? right->vertices : sep).push_back(node.vertices[k]);
  if (left->vertices.empty() || right->vertices.empty()) return;
  node.left = std::move(left);
  node.right = std::move(right);
  node.separator = std::move(sep);
  std::vector<int>().swap(node.vertices);
}

// Below this many rows the root is split by METIS as well: it takes tens of milliseconds there,
// and the coarse separator's fill is relatively higher (+5 % on a 22k-row k = 3 plane against
// +2-4 % from 300k rows on).
constexpr Eigen::Index kCoarseRootRows = 100000;

// The root by the coarse separator (a quarter of METIS's time on the whole graph, which is on
// every core's critical path); the nodes below by METIS. False if it found no split.
bool split_root(const Eigen::SparseMatrix<double>& lower, Node& node) {
  if (lower.rows() < kCoarseRootRows) return false;
  const std::vector<int> side = coarse_separator(lower);
  if (side.empty()) return false;
  auto left = std::make_unique<Node>(), right = std::make_unique<Node>();
  for (std::size_t k = 0; k < node.vertices.size(); ++k)
    (side[k] == 0 ? left->vertices : side[k] == 1 ? right->vertices : node.separator).push_back(node.vertices[k]);
  node.left = std::move(left);
  node.right = std::move(right);
  std::vector<int>().swap(node.vertices);
  return true;
}

bool order_leaf(const Eigen::SparseMatrix<double>& lower, Node& node, const std::vector<int>& label,
                const std::vector<int>& local, LeafOrdering how) {
  SubPattern sub;
  extract(lower, node.vertices, label, local, sub);
  std::vector<int> perm(node.vertices.size());
  Common common;
  const int ok = how == LeafOrdering::Amd ? cholmod_amd(&sub.view, nullptr, 0, perm.data(), &common.c)
                                          : cholmod_metis(&sub.view, nullptr, 0, 0, perm.data(), &common.c);
  if (!ok || common.c.status < CHOLMOD_OK) return false;
  node.order.resize(perm.size());
  for (std::size_t k = 0; k < perm.size(); ++k) node.order[k] = node.vertices[static_cast<std::size_t>(perm[k])];
  return true;
}

// The CPU time of f() on the calling thread (a task's time on a core of its own).
template <class F>
double cpu_ms_of(const F& f) {
  const double start = PhaseClock::thread_cpu_ms();
  f();
  return PhaseClock::thread_cpu_ms() - start;
}

void append_order(const Node& node, std::vector<int>& out) {
  if (!node.left) {
    out.insert(out.end(), node.order.begin(), node.order.end());
    return;
  }
  append_order(*node.left, out);
  append_order(*node.right, out);
  out.insert(out.end(), node.separator.begin(), node.separator.end());
}

}  // namespace

std::vector<int> nested_dissection(const Eigen::SparseMatrix<double>& lower, int parts, DissectionTimes* times,
                                   LeafOrdering how) {
  const auto n = static_cast<std::size_t>(lower.rows());
  if (n == 0 || lower.rows() != lower.cols() || !lower.isCompressed()) return {};
  Node root;
  root.vertices.resize(n);
  for (std::size_t k = 0; k < n; ++k) root.vertices[k] = static_cast<int>(k);
  std::vector<int> label(n, 0), local(n, 0);
  // Split level by level, each level's nodes concurrently.
  std::vector<Node*> level{&root}, leaves;
  for (int width = 1; width < parts && !level.empty(); width *= 2) {
    std::vector<Node*> splittable;
    for (Node* node : level) (node->vertices.size() >= kMinSplit ? splittable : leaves).push_back(node);
    label_nodes(splittable, label, local);
    std::vector<double> ms(splittable.size());
    run_tasks(static_cast<int>(splittable.size()), [&](int t) {
      const auto i = static_cast<std::size_t>(t);
      ms[i] = cpu_ms_of([&] {
        if (width > 1 || !split_root(lower, *splittable[i])) split(lower, *splittable[i], label, local);
      });
    });
    if (times) times->split_ms.push_back(std::move(ms));
    level.clear();
    for (Node* node : splittable) {
      if (!node->left) {
        leaves.push_back(node);
        continue;
      }
      level.push_back(node->left.get());
      level.push_back(node->right.get());
    }
  }
  leaves.insert(leaves.end(), level.begin(), level.end());
  // Largest first, so that the longest task does not start last.
  std::sort(leaves.begin(), leaves.end(), [](const Node* a, const Node* b) { return a->vertices.size() > b->vertices.size(); });
  label_nodes(leaves, label, local);
  std::vector<char> ok(leaves.size(), 0);
  std::vector<double> ms(leaves.size());
  run_tasks(static_cast<int>(leaves.size()), [&](int t) {
    const auto i = static_cast<std::size_t>(t);
    ms[i] = cpu_ms_of([&] { ok[i] = order_leaf(lower, *leaves[i], label, local, how); });
  });
  if (times) times->leaf_ms = std::move(ms);
  if (std::find(ok.begin(), ok.end(), 0) != ok.end()) return {};
  std::vector<int> out;
  out.reserve(n);
  append_order(root, out);
  return out;
}

double cholesky_fill(const Eigen::SparseMatrix<double>& lower, std::vector<int> perm, LeafOrdering whole) {
  if (lower.rows() == 0) return 0;
  SubPattern sub;
  std::vector<int> all(static_cast<std::size_t>(lower.cols()));
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  std::vector<int> label(all.size(), 0);
  extract(lower, all, label, all, sub);
  Common common;
  common.c.nmethods = 1;
  common.c.method[0].ordering = whole == LeafOrdering::Amd ? CHOLMOD_AMD : CHOLMOD_METIS;
  common.c.supernodal = CHOLMOD_SUPERNODAL;
  cholmod_factor* f =
      perm.empty() ? cholmod_analyze(&sub.view, &common.c) : analyze_supernodal_given(sub.view, perm.data(), &common.c);
  const double lnz = f ? common.c.lnz : 0.0;
  cholmod_free_factor(&f, &common.c);
  return lnz;
}
#else
std::vector<int> nested_dissection(const Eigen::SparseMatrix<double>&, int, DissectionTimes*, LeafOrdering) {
  return {};
}
double cholesky_fill(const Eigen::SparseMatrix<double>&, std::vector<int>, LeafOrdering) { return 0; }
#endif

}  // namespace freeform
