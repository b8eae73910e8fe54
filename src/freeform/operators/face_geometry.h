// Internal to freeform_operators: per-triangle cotangents, area and the degenerate-face policy
// shared by the cotangent Laplacian and the mixed Voronoi areas (docs/operators.md).
#pragma once

#include "freeform/mesh/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace freeform::detail {

// A face with 2 * area <= kDegenerateRatio * (longest edge)^2 (or 0) is degenerate: it
// contributes neither weights nor area.
inline constexpr double kDegenerateRatio = 1e-12;
// |cot| of a corner of a non-degenerate face is clamped to this bound (angle ~0.00057 deg
// from 0 or 180). Negative cotangents of obtuse corners are kept as they are.
inline constexpr double kCotClamp = 1e5;

// Corner k of a face is vertex v[k]; it lies opposite halfedge h[k].
struct FaceCorners {
  std::array<Vertex, 3> v;
  std::array<Halfedge, 3> h;
};

// Uses only halfedge(f), next() and to_vertex(): for h0 = a->b, h1 = b->c, h2 = c->a the
// corners are c (opposite h0), a (opposite h1), b (opposite h2).
inline FaceCorners face_corners(const Mesh& mesh, Face f) {
  const Halfedge h0 = mesh.halfedge(f);
  const Halfedge h1 = mesh.next(h0);
  const Halfedge h2 = mesh.next(h1);
  return {{mesh.to_vertex(h1), mesh.to_vertex(h2), mesh.to_vertex(h0)}, {h0, h1, h2}};
}

struct TriangleGeometry {
  double double_area = 0.0;        // |(p1 - p0) x (p2 - p0)|
  std::array<double, 3> dot{};     // dot of the two edge vectors leaving corner k
  std::array<double, 3> sq_len{};  // squared length of the edge opposite corner k
  bool degenerate = true;

  // Unclamped cotangent of corner k (only for non-degenerate faces).
  double cot(int k) const { return dot[static_cast<std::size_t>(k)] / double_area; }
};

inline TriangleGeometry triangle_geometry(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  TriangleGeometry g;
  const Vec3 e0 = p2 - p1;  // opposite corner 0
  const Vec3 e1 = p0 - p2;  // opposite corner 1
  const Vec3 e2 = p1 - p0;  // opposite corner 2
  g.sq_len = {e0.squaredNorm(), e1.squaredNorm(), e2.squaredNorm()};
  g.dot = {-e2.dot(e1), -e0.dot(e2), -e1.dot(e0)};
  g.double_area = e2.cross(-e1).norm();
  const double longest = std::max({g.sq_len[0], g.sq_len[1], g.sq_len[2]});
  g.degenerate = !(g.double_area > kDegenerateRatio * longest) || !std::isfinite(g.double_area);
  return g;
}

// The weights one triangle gives its corners, for both the global operators (operators.h) and
// the local BCM assembly: the clamped cotangent of each corner (it weights the opposite edge)
// and each corner's mixed Voronoi area (Meyer et al. 2003: Voronoi part for non-obtuse
// triangles, else half / a quarter of the area). A degenerate face gives nothing.
struct CornerWeights {
  bool degenerate = true;
  std::array<double, 3> cot{};   // clamped to +-kCotClamp
  std::array<double, 3> area{};  // sums to the triangle's area
  int clamped = 0;               // how many cotangents were clamped
};

inline CornerWeights corner_weights(const TriangleGeometry& g) {
  CornerWeights w;
  if (g.degenerate) return w;
  w.degenerate = false;
  for (int k = 0; k < 3; ++k) {
    const double cot = g.cot(k);
    w.clamped += std::abs(cot) > kCotClamp ? 1 : 0;
    w.cot[static_cast<std::size_t>(k)] = std::clamp(cot, -kCotClamp, kCotClamp);
  }
  const double a = 0.5 * g.double_area;
  int obtuse = -1;
  for (int k = 0; k < 3; ++k)
    if (g.dot[static_cast<std::size_t>(k)] < 0.0) obtuse = k;
  for (int k = 0; k < 3; ++k) {
    const auto k1 = static_cast<std::size_t>((k + 1) % 3), k2 = static_cast<std::size_t>((k + 2) % 3);
    // Voronoi part of corner k: (|e_k k1|^2 cot(k2) + |e_k k2|^2 cot(k1)) / 8 with the unclamped
    // cotangents (the edge k-k1 is opposite k2, the edge k-k2 opposite k1).
    w.area[static_cast<std::size_t>(k)] =
        obtuse < 0 ? (g.sq_len[k2] * g.cot(static_cast<int>(k2)) + g.sq_len[k1] * g.cot(static_cast<int>(k1))) / 8.0
                   : (obtuse == k ? 0.5 * a : 0.25 * a);
  }
  return w;
}
inline CornerWeights corner_weights(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  return corner_weights(triangle_geometry(p0, p1, p2));
}

// Vertex areas below 1e-12 of the mean vertex area are floored to it, so 1 / (2 A) stays finite.
inline constexpr double kAreaFloorRatio = 1e-12;

// Throws InvalidInput unless `positions` has one finite entry per vertex of `mesh`.
void check_positions(const Mesh& mesh, const VertexData<Vec3>& positions, const char* function);

}  // namespace freeform::detail
