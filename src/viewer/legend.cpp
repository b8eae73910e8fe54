#include "viewer/legend.h"

#include "viewer/region_colors.h"

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wold-style-cast"
#pragma GCC diagnostic ignored "-Wpedantic"
#endif
#include <stb/stb_easy_font.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#include <algorithm>
#include <cmath>
#include <string>

namespace freeform::viewer {
namespace {

struct Canvas {
  std::vector<std::uint8_t>& rgba;
  int width, height;

  void fill(int x0, int y0, int x1, int y1, const Rgb& c) {
    for (int y = std::max(y0, 0); y < std::min(y1, height); ++y)
      for (int x = std::max(x0, 0); x < std::min(x1, width); ++x) {
        std::uint8_t* p = &rgba[(static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 4];
        for (std::size_t k = 0; k < 3; ++k) p[k] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(c[k], 0.0f, 1.0f)));
        p[3] = 255;
      }
  }

  // stb_easy_font's quads are axis-aligned rectangles: 4 vertices of (x, y, z, rgba) each.
  void text(int x, int y, const std::string& s, int scale) {
    std::vector<float> buffer(16 * 600);
    const int quads = stb_easy_font_print(0.0f, 0.0f, const_cast<char*>(s.c_str()), nullptr, buffer.data(),
                                          static_cast<int>(buffer.size() * sizeof(float)));
    for (int q = 0; q < quads; ++q) {
      const float* v = buffer.data() + q * 16;
      const auto px = [&](float a) { return static_cast<int>(std::lround(a * static_cast<float>(scale))); };
      fill(x + px(v[0]), y + px(v[1]), x + px(v[8]), y + px(v[9]), {0.15f, 0.15f, 0.18f});
    }
  }
};

}  // namespace

void draw_smoothness_legend(std::vector<std::uint8_t>& rgba, int width, int height, int order) {
  if (order < 2 || width < 160 || height < 60) return;
  const int scale = width >= 900 ? 2 : 1;
  const int bar_w = 120 * scale, bar_h = 10 * scale, pad = 8 * scale, line = 12 * scale;
  const int x0 = pad, y_bar = height - pad - line - bar_h;
  Canvas canvas{rgba, width, height};
  canvas.fill(x0 - 4 * scale, y_bar - line - 6 * scale, x0 + bar_w + 10 * scale, height - pad / 2, {1.0f, 1.0f, 1.0f});
  canvas.text(x0, y_bar - line, "boundary smoothness", scale);
  const int top = order - 1;
  for (int x = 0; x < bar_w; ++x)
    canvas.fill(x0 + x, y_bar, x0 + x + 1, y_bar + bar_h, smoothness_color(top * (x + 0.5) / bar_w));
  for (int c = 0; c <= top; ++c) {
    const int x = x0 + c * (bar_w - 1) / top;
    canvas.fill(x, y_bar + bar_h, x + scale, y_bar + bar_h + 3 * scale, {0.15f, 0.15f, 0.18f});
    const std::string label = "C" + std::to_string(c);
    canvas.text(std::clamp(x - 5 * scale, x0, x0 + bar_w - 10 * scale), y_bar + bar_h + 4 * scale, label, scale);
  }
}

}  // namespace freeform::viewer
