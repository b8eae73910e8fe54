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

int n_movable(const Edit& edit) {
  return static_cast<int>(std::count_if(edit.handles.begin(), edit.handles.end(), [](const EditHandle& h) { return h.movable; }));
}

Regions edit_regions(const Mesh& mesh, const Edit& edit) {
  std::vector<HandleRegion> handles;
  handles.reserve(edit.handles.size());
  for (const EditHandle& h : edit.handles) handles.push_back(HandleRegion{h.vertices, h.movable});
  return Regions(mesh, edit.support, std::move(handles));
}

}  // namespace freeform
