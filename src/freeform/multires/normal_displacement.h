// The normal-displacement fit of docs/multires.md for one point and one base triangle.
//
// Triangle corners a, b, c with vertex normals na, nb, nc. The point x lies on the triangle
// offset by h along the interpolated normals iff
//     det[ (a + h na) - (c + h nc), (b + h nb) - (c + h nc), x - (c + h nc) ] = 0,
// a cubic in h. For each real root the barycentrics follow from a 2x2 least-squares solve and
// are polished together with h by Newton's method on
//     F(u, v, h) = u (a + h na) + v (b + h nb) + w (c + h nc) - x,  w = 1 - u - v.
#pragma once

#include "freeform/mesh/types.h"
#include "freeform/numerics/cubic.h"

namespace freeform::multires {

struct NormalFit {
  bool ok = false;
  double u = 0, v = 0, w = 0, h = 0;
  double det = 0;  // det dF/d(u, v, h): > 0 where the offset map is locally injective and oriented
};

// Best fit (smallest |h|) on one triangle with every barycentric >= -tolerance, or ok = false.
NormalFit fit_normal_displacement(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na,
                                  const Vec3& nb, const Vec3& nc, double tolerance);

// A lower bound on |h| of any fit fit_normal_displacement(x, a, b, c, ..., tolerance) accepts,
// whatever the normals: x - h * (interpolated normal) lies in the tolerance-expanded triangle and
// that normal is at most 1 + 4 tolerance long, so |h| >= dist(x, expanded triangle) / that.
// Cheap (no cubic): the candidate search skips triangles that cannot beat its best |h|.
double fit_height_lower_bound(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double tolerance);

// det dF/d(u, v, h) at (u, v, h): the sign of the offset map's Jacobian (overlap test).
inline double offset_jacobian_det(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb,
                                  const Vec3& nc, double u, double v, double w, double h) {
  const Vec3 e1 = (a - c) + h * (na - nc);
  const Vec3 e2 = (b - c) + h * (nb - nc);
  const Vec3 n = u * na + v * nb + w * nc;
  return e1.cross(e2).dot(n);
}

// The same determinant along the ray s -> (u, v, s): det(s) = a0 + a1 s + a2 s^2, where a0 is
// the base triangle's own orientation. Where the base bends tighter than |h| (a focal point of
// the offset surface), det changes sign between 0 and h.
struct JacobianRay {
  double a0 = 0, a1 = 0, a2 = 0;
  double at(double s) const { return a0 + s * (a1 + s * a2); }
};
inline JacobianRay offset_jacobian_ray(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na, const Vec3& nb,
                                       const Vec3& nc, double u, double v, double w) {
  const Vec3 n = u * na + v * nb + w * nc;
  const Vec3 e1 = a - c, e2 = b - c, d1 = na - nc, d2 = nb - nc;
  return {e1.cross(e2).dot(n), (e1.cross(d2) + d1.cross(e2)).dot(n), d1.cross(d2).dot(n)};
}

// The height to rebuild with so that det keeps at least `min_ratio` * a0 (graceful degradation
// at a focal point): h itself where it does, else the first s between 0 and h with
// det(s) = min_ratio * a0 (the detail is flattened just enough), 0 if the base triangle itself
// is inverted (a0 <= 0). Continuous in the base, so a bend that tightens flattens smoothly.
double safe_height(const JacobianRay& j, double h, double min_ratio);

}  // namespace freeform::multires
