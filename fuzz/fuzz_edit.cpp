// libFuzzer target for edit files (parse_edit_text on a fixed 11 x 11 grid, then the regions
// and transforms an EditSolver would build from it): freeform::Error is the only way out.
#include "freeform/common/error.h"
#include "freeform/edit/edit.h"
#include "freeform/edit/edit_json.h"
#include "freeform/mesh/generators.h"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const freeform::Mesh mesh = freeform::Mesh::from_soup(freeform::make_plane(10, 10));
  try {
    const freeform::Edit edit =
        freeform::parse_edit_text(std::string_view(reinterpret_cast<const char*>(data), size), mesh, "fuzz.json", ".");
    const freeform::Regions regions = freeform::edit_regions(mesh, edit);
    for (const freeform::EditHandle& h : edit.handles)
      if (h.movable && !h.matrix) (void)h.manipulator.to_affine(freeform::Vec3::Zero());
    (void)freeform::edit_to_json(edit);
  } catch (const freeform::InternalError&) {
    throw;  // a bug: let it crash
  } catch (const freeform::Error&) {
  }
  return 0;
}
