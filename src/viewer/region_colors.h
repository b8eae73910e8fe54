// Region colours of the paper's Fig. 1 (GL-free): support (free) blue, movable handles green,
// fixed surface gray. Immovable handles act like fixed surface and are drawn a darker gray.
#pragma once

#include "viewer/render_scene.h"

#include "freeform/regions/regions.h"

#include <vector>

namespace freeform::viewer {

struct RegionPalette {
  Rgb free{0.30f, 0.50f, 0.95f};      // support: blue
  Rgb handle{0.25f, 0.80f, 0.30f};    // movable handle: green
  Rgb fixed{0.72f, 0.72f, 0.72f};     // outside the support: gray
  Rgb immovable{0.45f, 0.45f, 0.45f}; // immovable handle: dark gray
};

// Colour used when no edit is given.
inline constexpr Rgb kPlainColor{0.80f, 0.78f, 0.74f};

// One colour per vertex of the regions' mesh.
std::vector<Rgb> region_colors(const Regions& regions, const RegionPalette& palette = {});

}  // namespace freeform::viewer
