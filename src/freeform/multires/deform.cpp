// The one-shot deform() declared in bcm/edit.h. It lives here so that freeform_multires
// depends on freeform_bcm and not the reverse: with edit.multiresolution (the default) the
// detail is preserved (MultiresSolver), otherwise the support is the plain BCM surface.
#include "freeform/bcm/edit.h"
#include "freeform/bcm/edit_file.h"
#include "freeform/multires/multires_solver.h"

namespace freeform {

Mesh deform(const Mesh& mesh, const Edit& edit, BcmStats* stats) {
  check_edit_available(edit);
  const Regions regions = edit_regions(mesh, edit);
  Mesh out = mesh;
  if (edit.multiresolution) {
    const MultiresSolver solver(mesh, regions, solver_settings(edit));
    solver.evaluate(edit_transforms(edit, solver.bcm()), out.positions());
    if (stats) *stats = solver.bcm().stats();
  } else {
    const BcmSolver solver(mesh, regions, solver_settings(edit));
    solver.evaluate(edit_transforms(edit, solver), out.positions());
    if (stats) *stats = solver.stats();
  }
  return out;
}

}  // namespace freeform
