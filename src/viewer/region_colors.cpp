#include "viewer/region_colors.h"

#include <algorithm>

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

Rgb smoothness_color(double c) {
  static constexpr Rgb kStops[3] = {{0.90f, 0.18f, 0.12f}, {0.98f, 0.72f, 0.10f}, {0.58f, 0.30f, 0.88f}};
  const double t = std::clamp(c, 0.0, 2.0);
  const int i = std::min(static_cast<int>(t), 1);
  const auto f = static_cast<float>(t - i);
  Rgb out;
  for (std::size_t k = 0; k < 3; ++k) out[k] = kStops[i][k] + f * (kStops[i + 1][k] - kStops[i][k]);
  return out;
}

void color_smoothness_band(std::vector<Rgb>& colors, std::span<const Vertex> band, std::span<const double> smoothness) {
  for (Vertex v : band)
    colors[static_cast<std::size_t>(v.idx())] = smoothness_color(smoothness[static_cast<std::size_t>(v.idx())]);
}

}  // namespace freeform::viewer
