// Region colours of the paper's Fig. 1 (GL-free): support (free) blue, movable handles green,
// fixed surface gray. Immovable handles act like fixed surface and are drawn a darker gray.
#pragma once

#include "viewer/render_scene.h"

#include "freeform/regions/regions.h"

#include <span>
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

// Boundary smoothness c on one scale for every order: red at C0 (a crease), amber at C1,
// violet at C2, linear in between (c is clamped to [0, 2]).
Rgb smoothness_color(double c);

// Recolours the smoothness band (where c acts, as bcm/boundary_band.h's smoothness_band gives
// it) by smoothness_color of each band vertex's c (`smoothness`: one c per vertex, e.g.
// smoothness_per_vertex); `colors` has one entry per vertex.
void color_smoothness_band(std::vector<Rgb>& colors, std::span<const Vertex> band, std::span<const double> smoothness);

}  // namespace freeform::viewer
