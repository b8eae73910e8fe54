// Decoding PNGs (stb_image) and classifying pixels by colour for the render tests.
#pragma once

#include "viewer/camera.h"

#include <cstdint>
#include <string>
#include <vector>

namespace freeform::test {

struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // rows top first
  const std::uint8_t* at(int x, int y) const { return rgba.data() + 4 * (static_cast<std::size_t>(y) * width + x); }
};

// Empty image (width 0) if the file is not a PNG stb_image can read.
Image load_png(const std::string& path);
Image decode_png(const std::vector<std::uint8_t>& bytes);

enum class PixelClass { Background, Blue, Green, Gray, Other };

// Background: white (all channels >= 250). Blue/green: that channel clearly dominates.
// Gray: shaded neutral surface (channels within 14 of each other, below the background).
inline PixelClass classify(const std::uint8_t* p) {
  const int r = p[0], g = p[1], b = p[2];
  if (r >= 250 && g >= 250 && b >= 250) return PixelClass::Background;
  if (b > r + 40 && b > g + 15) return PixelClass::Blue;
  if (g > r + 40 && g > b + 40) return PixelClass::Green;
  if (std::abs(r - g) <= 14 && std::abs(g - b) <= 14 && std::abs(r - b) <= 14) return PixelClass::Gray;
  return PixelClass::Other;
}

// Pixel (column, row from the top) of a world point, for a width x height image.
inline Eigen::Vector2d project(const viewer::Camera& c, int width, int height, const Eigen::Vector3d& p) {
  const Eigen::Vector4d q = c.projection(static_cast<double>(width) / height) * c.view() * p.homogeneous();
  const double x = q.x() / q.w(), y = q.y() / q.w();
  return {(x + 1) * 0.5 * width, (1 - y) * 0.5 * height};
}

}  // namespace freeform::test
