#include "freeform/mesh/seams.h"

#include "freeform/mesh/validation.h"

#include <algorithm>

namespace freeform {

std::vector<std::array<Vertex, 2>> open_seam_pairs(const Mesh& mesh, const std::vector<Vertex>& vertices) {
  if (std::none_of(vertices.begin(), vertices.end(), [&](Vertex v) { return mesh.is_boundary(v); })) return {};
  std::vector<Vertex> boundary;
  std::vector<Vec3> positions;
  for (Vertex v : mesh.vertices())
    if (mesh.is_boundary(v)) {
      boundary.push_back(v);
      positions.push_back(mesh.position(v));
    }
  std::vector<Vertex> partner(static_cast<std::size_t>(mesh.n_vertices()));
  for (const auto& [a, b] : coincident_positions(positions)) {
    const Vertex va = boundary[static_cast<std::size_t>(a)], vb = boundary[static_cast<std::size_t>(b)];
    if (!partner[static_cast<std::size_t>(va.idx())].is_valid()) partner[static_cast<std::size_t>(va.idx())] = vb;
    if (!partner[static_cast<std::size_t>(vb.idx())].is_valid()) partner[static_cast<std::size_t>(vb.idx())] = va;
  }
  std::vector<std::array<Vertex, 2>> out;
  for (Vertex v : vertices)
    if (v.idx() >= 0 && v.idx() < mesh.n_vertices() && partner[static_cast<std::size_t>(v.idx())].is_valid())
      out.push_back({v, partner[static_cast<std::size_t>(v.idx())]});
  return out;
}

}  // namespace freeform
