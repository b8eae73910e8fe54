// The boundary-smoothness legend drawn into rendered pixels (GL-free): a colour bar of
// smoothness_color over [0, k-1] with "C0" ... labels (stb_easy_font), in the lower left.
#pragma once

#include <cstdint>
#include <vector>

namespace freeform::viewer {

// `rgba`: width x height RGBA8, top row first (OffscreenTarget::read_rgba). Order k in {2, 3};
// images too small for the legend (under 160 x 60 pixels) are left unchanged.
void draw_smoothness_legend(std::vector<std::uint8_t>& rgba, int width, int height, int order);

}  // namespace freeform::viewer
