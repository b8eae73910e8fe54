#include "freeform/io/triangulate.h"

#include <cmath>
#include <numbers>

namespace freeform::io_detail {
namespace {

// Convex and simple: every turn has the sign of the polygon's normal (straight corners
// allowed), and the turns add up to one revolution (a pentagram turns twice).
bool convex(const std::vector<int>& poly, std::span<const Vec3> positions) {
  const std::size_t n = poly.size();
  for (int v : poly)
    if (v < 0 || static_cast<std::size_t>(v) >= positions.size()) return false;
  const auto at = [&](std::size_t i) -> const Vec3& { return positions[static_cast<std::size_t>(poly[i % n])]; };
  Vec3 normal = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) normal += (at(i) - at(0)).cross(at(i + 1) - at(0));
  if (!(normal.norm() > 0.0) || !normal.allFinite()) return false;
  double turned = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 in = at(i + 1) - at(i), out = at(i + 2) - at(i + 1);
    if (!(in.norm() > 0.0)) return false;  // a repeated corner
    const Vec3 c = in.cross(out);
    if (c.dot(normal) < 0.0) return false;
    turned += std::atan2(c.norm(), in.dot(out));
  }
  return std::abs(turned - 2.0 * std::numbers::pi) < 1e-6;
}

// A strip across the polygon: triangles alternately on the chord's two sides, so that no corner
// is in more than four of them.
void strip(const std::vector<int>& poly, std::vector<Tri>& faces) {
  std::size_t l = 0, r = poly.size() - 1;
  for (bool left = true; r - l >= 2; left = !left) {
    if (left) {
      faces.push_back({poly[l], poly[l + 1], poly[r]});
      ++l;
    } else {
      faces.push_back({poly[l], poly[r - 1], poly[r]});
      --r;
    }
  }
}

}  // namespace

bool triangulate_polygon(const std::vector<int>& poly, std::span<const Vec3> positions, std::vector<Tri>& faces) {
  if (poly.size() > kFanCorners && convex(poly, positions)) {
    strip(poly, faces);
    return true;
  }
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) faces.push_back({poly[0], poly[i], poly[i + 1]});
  return false;
}

}  // namespace freeform::io_detail
