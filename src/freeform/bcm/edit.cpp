#include "freeform/bcm/edit.h"

#include "freeform/bcm/edit_file.h"
#include "freeform/common/error.h"

#include <algorithm>

namespace freeform {

std::vector<Eigen::Affine3d> edit_transforms(const Edit& edit, const BcmSolver& solver) {
  const auto movable = std::count_if(edit.handles.begin(), edit.handles.end(), [](const EditHandle& h) { return !h.fixed; });
  if (movable != solver.n_movable())
    throw InvalidInput("the edit has " + std::to_string(movable) + " movable handles, the solver " +
                       std::to_string(solver.n_movable()) + ": build the solver from this edit");
  std::vector<Eigen::Affine3d> out;
  for (const EditHandle& h : edit.handles) {
    if (h.fixed) continue;
    const int m = static_cast<int>(out.size());
    out.push_back(h.matrix ? *h.matrix : h.manipulator.to_affine(solver.handle_centroid(m)));
  }
  return out;
}

BcmSettings solver_settings(const Edit& edit) {
  BcmSettings s = edit.settings;
  s.anisotropic = s.anisotropic || edit.anisotropic;
  return s;
}

}  // namespace freeform
