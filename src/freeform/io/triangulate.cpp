#include "freeform/io/triangulate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace freeform::io_detail {
namespace {

using Point = std::array<double, 2>;

double cross(const Point& a, const Point& b, const Point& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// The polygon projected onto the coordinate plane most nearly parallel to it, counter-clockwise
// (the plane's axes swapped where its normal points the other way). Empty where a corner is not
// among `positions` or the polygon has no area.
std::vector<Point> projected(const std::vector<int>& poly, std::span<const Vec3> positions) {
  for (int v : poly)
    if (v < 0 || static_cast<std::size_t>(v) >= positions.size()) return {};
  const auto at = [&](std::size_t i) -> const Vec3& {
    return positions[static_cast<std::size_t>(poly[i % poly.size()])];
  };
  Vec3 normal = Vec3::Zero();
  for (std::size_t i = 0; i < poly.size(); ++i) normal += (at(i) - at(0)).cross(at(i + 1) - at(0));
  if (!(normal.norm() > 0.0) || !normal.allFinite()) return {};
  Eigen::Index drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  Eigen::Index u = (drop + 1) % 3, w = (drop + 2) % 3;
  if (normal[drop] < 0.0) std::swap(u, w);
  std::vector<Point> out(poly.size());
  for (std::size_t i = 0; i < poly.size(); ++i) out[i] = {at(i)[u], at(i)[w]};
  return out;
}

// Convex and simple: no corner turns clockwise, and the turns add up to one revolution (a
// pentagram turns twice).
bool convex(const std::vector<Point>& p) {
  const std::size_t n = p.size();
  double turned = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Point &a = p[i], &b = p[(i + 1) % n], &c = p[(i + 2) % n];
    const double turn = cross(a, b, c);
    if (turn < 0.0 || (a == b)) return false;
    turned += std::atan2(turn, (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]));
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

// Ear clipping: repeatedly cuts off a corner that turns counter-clockwise and whose triangle
// holds no other remaining corner. False (nothing appended) where no such corner is left before
// the end (a polygon that crosses itself), or after 8 n^2 corner tests (a file built to make
// every corner but one fail would take n^3).
bool clip_ears(const std::vector<int>& poly, const std::vector<Point>& p, std::vector<Tri>& faces) {
  const std::size_t n = p.size();
  std::size_t budget = 8 * n * n;
  std::vector<std::size_t> next(n), prev(n);
  for (std::size_t i = 0; i < n; ++i) next[i] = (i + 1) % n, prev[i] = (i + n - 1) % n;
  const auto inside = [&](std::size_t a, std::size_t b, std::size_t c, std::size_t j) {
    return cross(p[a], p[b], p[j]) >= 0.0 && cross(p[b], p[c], p[j]) >= 0.0 && cross(p[c], p[a], p[j]) >= 0.0;
  };
  const auto ear = [&](std::size_t b) {
    const std::size_t a = prev[b], c = next[b];
    if (!(cross(p[a], p[b], p[c]) > 0.0)) return false;
    for (std::size_t j = next[c]; j != a; j = next[j]) {
      if (budget > 0) --budget;
      if (inside(a, b, c, j)) return false;
    }
    return true;
  };
  const std::size_t first = faces.size();
  std::size_t b = 0;
  for (std::size_t left = n, misses = 0; left > 3;) {
    if (ear(b)) {
      faces.push_back({poly[prev[b]], poly[b], poly[next[b]]});
      next[prev[b]] = next[b];
      prev[next[b]] = prev[b];
      b = prev[b];
      --left;
      misses = 0;
    } else if (++misses > left || budget == 0) {
      faces.resize(first);
      return false;
    } else {
      b = next[b];
    }
  }
  faces.push_back({poly[prev[b]], poly[b], poly[next[b]]});
  return true;
}

bool repeats_a_corner(std::vector<int> poly) {
  std::sort(poly.begin(), poly.end());
  return std::adjacent_find(poly.begin(), poly.end()) != poly.end();
}

}  // namespace

Cut triangulate_polygon(const std::vector<int>& poly, std::span<const Vec3> positions, std::vector<Tri>& faces) {
  if (poly.size() > 3) {
    const std::vector<Point> p = projected(poly, positions);
    if (!p.empty() && convex(p)) {
      if (poly.size() > kFanCorners) {
        strip(poly, faces);
        return Cut::Strip;
      }
    } else if (!p.empty() && poly.size() <= kMaxEarCorners && !repeats_a_corner(poly) && clip_ears(poly, p, faces)) {
      return Cut::Ears;
    }
  }
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) faces.push_back({poly[0], poly[i], poly[i + 1]});
  return Cut::Fan;
}

}  // namespace freeform::io_detail
