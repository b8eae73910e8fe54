#include "freeform/edit/edit.h"

#include <algorithm>

namespace freeform {

std::string_view deformation_name(Deformation d) {
  switch (d) {
    case Deformation::Linear: return "linear";
    case Deformation::Nonlinear: return "nonlinear";
  }
  return "unknown";
}

std::optional<Deformation> deformation_from_name(std::string_view name) {
  for (Deformation d : kDeformations)
    if (name == deformation_name(d)) return d;
  return std::nullopt;
}

int n_movable(const Edit& edit) {
  return static_cast<int>(std::count_if(edit.handles.begin(), edit.handles.end(), [](const EditHandle& h) { return h.movable; }));
}

Regions edit_regions(const Mesh& mesh, const Edit& edit) {
  std::vector<HandleRegion> handles;
  handles.reserve(edit.handles.size());
  for (const EditHandle& h : edit.handles) handles.push_back(HandleRegion{h.vertices, h.movable});
  // Isolated vertices (in no face) have no neighbours to bend with: they stay where they are.
  std::vector<Vertex> support;
  support.reserve(edit.support.size());
  for (Vertex v : edit.support)
    if (v.idx() < 0 || v.idx() >= mesh.n_vertices() || mesh.halfedge(v).is_valid()) support.push_back(v);
  return Regions(mesh, support, std::move(handles));
}

}  // namespace freeform
