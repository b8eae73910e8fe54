#include "viewer/region_colors.h"

namespace freeform::viewer {

std::vector<Rgb> region_colors(const Regions& regions, const RegionPalette& palette) {
  std::vector<Rgb> out(static_cast<std::size_t>(regions.n_vertices()), palette.fixed);
  for (int i = 0; i < regions.n_vertices(); ++i) {
    const Vertex v(i);
    switch (regions.role(v)) {
      case Role::Fixed: break;
      case Role::Free: out[static_cast<std::size_t>(i)] = palette.free; break;
      case Role::Handle:
        out[static_cast<std::size_t>(i)] =
            regions.handles()[static_cast<std::size_t>(regions.handle_of(v))].movable ? palette.handle : palette.immovable;
        break;
    }
  }
  return out;
}

}  // namespace freeform::viewer
