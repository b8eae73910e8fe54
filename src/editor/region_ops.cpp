#include "editor/region_ops.h"

#include "freeform/common/error.h"
#include "freeform/mesh/traversal.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>

namespace freeform::editor {
namespace {

void check_vertex(const Mesh& mesh, Vertex v, const char* what) {
  if (!v.is_valid() || v.idx() >= mesh.n_vertices())
    throw InvalidInput(std::string(what) + ": vertex " + std::to_string(v.idx()) + " is not in the mesh (it has " +
                       std::to_string(mesh.n_vertices()) + " vertices)");
}

// Membership flags of a checked set.
std::vector<char> flags(const Mesh& mesh, std::span<const Vertex> set, const char* what) {
  std::vector<char> in(static_cast<std::size_t>(mesh.n_vertices()), 0);
  for (Vertex v : set) {
    check_vertex(mesh, v, what);
    in[v.idx()] = 1;
  }
  return in;
}

void check_rings(int rings, const char* what) {
  if (rings < 0) throw InvalidInput(std::string(what) + ": the ring count must be >= 0, got " + std::to_string(rings));
}

}  // namespace

std::vector<Vertex> grow_rings(const Mesh& mesh, std::span<const Vertex> set, int rings) {
  check_rings(rings, "grow");
  for (Vertex v : set) check_vertex(mesh, v, "grow");
  const VertexData<int> dist = ring_distance(mesh, set, rings);
  std::vector<Vertex> out;
  for (Vertex v : mesh.vertices())
    if (dist[v] >= 0) out.push_back(v);
  return out;
}

std::vector<Vertex> shrink_rings(const Mesh& mesh, std::span<const Vertex> set, int rings) {
  check_rings(rings, "shrink");
  const std::vector<char> in = flags(mesh, set, "shrink");
  // The nearest unselected vertex of any set vertex is reached through an unselected vertex
  // adjacent to the set, so those are the only seeds needed.
  std::vector<Vertex> seeds;
  if (rings > 0)
    for (Vertex v : mesh.vertices()) {
      if (in[v.idx()]) continue;
      for (Halfedge h : mesh.outgoing(v))
        if (in[mesh.to_vertex(h).idx()]) {
          seeds.push_back(v);
          break;
        }
    }
  const VertexData<int> dist = ring_distance(mesh, seeds, rings);
  std::vector<Vertex> out;
  for (Vertex v : mesh.vertices())
    if (in[v.idx()] && dist[v] < 0) out.push_back(v);
  return out;
}

std::vector<Vertex> geodesic_flood(const Mesh& mesh, const VertexData<Vec3>& positions, Vertex seed, double radius) {
  check_vertex(mesh, seed, "geodesic flood");
  if (static_cast<int>(positions.size()) != mesh.n_vertices())
    throw InvalidInput("geodesic flood: got " + std::to_string(positions.size()) + " positions for a mesh with " +
                       std::to_string(mesh.n_vertices()) + " vertices");
  if (!std::isfinite(radius) || radius < 0.0)
    throw InvalidInput("geodesic flood: the radius must be a finite number >= 0, got " + std::to_string(radius));
  // Dijkstra like geodesic_distance (selectors.h), but on the given positions and touching
  // only the vertices reached.
  std::vector<double> dist(static_cast<std::size_t>(mesh.n_vertices()), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  std::vector<Vertex> out;
  dist[seed.idx()] = 0.0;
  queue.emplace(0.0, seed.idx());
  while (!queue.empty()) {
    const auto [d, i] = queue.top();
    queue.pop();
    if (d > dist[i]) continue;  // stale entry
    const Vertex v(i);
    out.push_back(v);
    for (Halfedge h : mesh.outgoing(v)) {
      const Vertex w = mesh.to_vertex(h);
      const double nd = d + (positions[w] - positions[v]).norm();
      if (nd < dist[w.idx()] && nd <= radius) {
        dist[w.idx()] = nd;
        queue.emplace(nd, w.idx());
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::vector<Vertex>> region_components(const Mesh& mesh, std::span<const Vertex> set) {
  std::vector<char> in = flags(mesh, set, "region components");  // cleared once a vertex is placed
  std::vector<std::vector<Vertex>> pieces;
  std::vector<Vertex> stack;
  for (Vertex seed : mesh.vertices()) {  // ascending, so pieces come ordered by smallest vertex
    if (!in[seed.idx()]) continue;
    std::vector<Vertex> piece{seed};
    in[seed.idx()] = 0;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Vertex v = stack.back();
      stack.pop_back();
      for (Halfedge h : mesh.outgoing(v)) {
        const Vertex w = mesh.to_vertex(h);
        if (!in[w.idx()]) continue;
        in[w.idx()] = 0;
        piece.push_back(w);
        stack.push_back(w);
      }
    }
    std::sort(piece.begin(), piece.end());
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

}  // namespace freeform::editor
