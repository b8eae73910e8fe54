// Internal to freeform_operators: per-triangle cotangents, area and the degenerate-face policy
// shared by the cotangent Laplacian and the mixed Voronoi areas (DESIGN.md section 2).
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

// Throws InvalidInput unless `positions` has one finite entry per vertex of `mesh`.
void check_positions(const Mesh& mesh, const VertexData<Vec3>& positions, const char* function);

}  // namespace freeform::detail
