#include "editor/region_ops.h"

#include "freeform/common/error.h"
#include "freeform/mesh/traversal.h"
#include "freeform/regions/selectors.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  std::vector<Vertex> out;
  (void)geodesic_distance(mesh, positions, seed, radius, &out);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::vector<Vertex>> region_components(const Mesh& mesh, std::span<const Vertex> set) {
  const std::vector<char> in = flags(mesh, set, "region components");
  int count = 0;
  const VertexData<int> piece = label_pieces(mesh, in, count);
  std::vector<std::vector<Vertex>> pieces(static_cast<std::size_t>(count));
  for (Vertex v : mesh.vertices())  // ascending: each piece comes out sorted
    if (piece[v] >= 0) pieces[static_cast<std::size_t>(piece[v])].push_back(v);
  return pieces;
}

}  // namespace freeform::editor
