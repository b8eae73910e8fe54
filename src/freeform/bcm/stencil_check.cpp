#include "freeform/bcm/stencil_check.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"

#include <atomic>
#include <string>
#include <unordered_set>

namespace freeform {
namespace {

// Per vertex its valence and a bound on its 2-ring, memoized (-1: not yet; written by several
// threads, always the same value). A bound past kMaxStencil is not summed further.
class RingBounds {
 public:
  explicit RingBounds(const Mesh& mesh)
      : mesh_(mesh),
        valence_(static_cast<std::size_t>(mesh.n_vertices()), -1),
        ring2_(static_cast<std::size_t>(mesh.n_vertices()), -1) {}

  int valence(Vertex v) {
    std::atomic_ref<int> slot(valence_[v]);
    int n = slot.load(std::memory_order_relaxed);
    if (n < 0) slot.store(n = mesh_.valence(v), std::memory_order_relaxed);
    return n;
  }
  // Its closed neighbourhood's valences, plus one each.
  long ring2(Vertex v) {
    std::atomic_ref<long> slot(ring2_[v]);
    long bound = slot.load(std::memory_order_relaxed);
    if (bound >= 0) return bound;
    bound = valence(v) + 1;
    for (Halfedge h : mesh_.outgoing(v)) {
      bound += valence(mesh_.to_vertex(h)) + 1;
      if (bound > kMaxStencil) break;
    }
    slot.store(bound, std::memory_order_relaxed);
    return bound;
  }
  // Its closed neighbourhood's 2-ring bounds.
  long ring3(Vertex v) {
    long bound = ring2(v);
    for (Halfedge h : mesh_.outgoing(v)) {
      if (bound > kMaxStencil) break;
      bound += ring2(mesh_.to_vertex(h));
    }
    return bound;
  }
  long ring(Vertex v, int k) { return k == 2 ? ring2(v) : ring3(v); }

 private:
  const Mesh& mesh_;
  VertexData<int> valence_;
  VertexData<long> ring2_;
};

struct RingCount {
  bool over = false;  // the k-ring holds more than kMaxStencil vertices
  Vertex worst;       // the highest valence within k - 1 rings
};

// v's k-ring counted breadth-first, stopping past kMaxStencil (the walk never reads more of a
// huge fan than that).
RingCount count_ring(const Mesh& mesh, Vertex v, int k) {
  RingCount out{false, v};
  int worst_valence = -1;
  std::unordered_set<int> seen{v.idx()};
  std::vector<Vertex> frontier{v}, next;
  for (int depth = 0; depth < k && !out.over; ++depth) {
    next.clear();
    for (Vertex u : frontier) {
      if (const int d = mesh.valence(u); d > worst_valence) {
        worst_valence = d;
        out.worst = u;
      }
      for (Halfedge h : mesh.outgoing(u)) {
        const Vertex w = mesh.to_vertex(h);
        if (!seen.insert(w.idx()).second) continue;
        next.push_back(w);
        if (static_cast<long>(seen.size()) > kMaxStencil) {
          out.over = true;
          break;
        }
      }
      if (out.over) break;
    }
    std::swap(frontier, next);
  }
  return out;
}

}  // namespace

void check_stencil_size(const Mesh& mesh, const std::vector<Vertex>& free, int k) {
  if (k < 2) return;
  RingBounds bounds(mesh);
  const auto over = [&](Vertex v) { return bounds.ring(v, k) > kMaxStencil && count_ring(mesh, v, k).over; };
  // The first free vertex in order whose ring passes: the same refusal on any number of threads.
  const auto n = static_cast<std::ptrdiff_t>(free.size());
  std::atomic<std::ptrdiff_t> first{n};
  parallel_for(n, 8192, [&](std::ptrdiff_t begin, std::ptrdiff_t end) {
    for (auto i = begin; i < end && i < first.load(std::memory_order_relaxed); ++i)
      if (over(free[static_cast<std::size_t>(i)])) {
        std::ptrdiff_t seen = first.load();
        while (i < seen && !first.compare_exchange_weak(seen, i)) {
        }
        return;
      }
  });
  if (first.load() == n) return;
  const Vertex v = free[static_cast<std::size_t>(first.load())];
  const Vertex worst = count_ring(mesh, v, k).worst;
  const std::string where =
      worst == v ? "free vertex " + std::to_string(v.idx())
                 : "vertex " + std::to_string(worst.idx()) + ", near free vertex " + std::to_string(v.idx()) + ",";
  throw InvalidInput(where + " has " + std::to_string(mesh.valence(worst)) + " neighbours: the order-" +
                     std::to_string(k) + " operator would couple more than " + std::to_string(kMaxStencil) +
                     " vertices in one row (memory grows with the square of the valence); remesh that fan, "
                     "keep the vertex out of the support, or use order 1");
}

}  // namespace freeform
