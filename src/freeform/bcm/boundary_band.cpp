#include "freeform/bcm/boundary_band.h"

#include "freeform/mesh/traversal.h"

namespace freeform {

std::vector<Vertex> smoothness_band(const Mesh& mesh, const Regions& regions, int order) {
  std::vector<Vertex> band;
  if (order < 2) return band;
  const VertexData<int> dist = ring_distance(mesh, regions.free_vertices(), order - 1);
  for (Vertex v : mesh.vertices())
    if (dist[v] >= 1) band.push_back(v);
  return band;
}

std::vector<double> smoothness_per_vertex(const Regions& regions, const BcmSettings& settings) {
  const double top = settings.order - 1.0;
  const double outer = resolved_outer(settings);
  const double inner = resolved_inner(settings);
  std::vector<double> c(static_cast<std::size_t>(regions.n_vertices()));
  for (int i = 0; i < regions.n_vertices(); ++i) {
    const Role r = regions.role(Vertex(i));
    c[static_cast<std::size_t>(i)] = r == Role::Free ? top : r == Role::Fixed ? outer : inner;
  }
  for (const SmoothnessSegment& s : settings.smoothness.segments)
    for (Vertex v : s.vertices)
      if (regions.role(v) != Role::Free) c[static_cast<std::size_t>(v.idx())] = s.value;
  return c;
}

}  // namespace freeform
