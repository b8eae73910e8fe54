#include "freeform/multires/normal_displacement.h"

#include <algorithm>
#include <cmath>

namespace freeform::multires {
NormalFit fit_normal_displacement(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& na,
                                  const Vec3& nb, const Vec3& nc, double tolerance) {
  const Vec3 E1 = a - c, E2 = b - c, X = x - c;
  const Vec3 N1 = na - nc, N2 = nb - nc, N3 = -nc;
  const Vec3 e12 = E1.cross(E2);
  const Vec3 lin = E1.cross(N2) + N1.cross(E2);
  const Vec3 n12 = N1.cross(N2);
  const double c0 = e12.dot(X);
  const double c1 = e12.dot(N3) + lin.dot(X);
  const double c2 = lin.dot(N3) + n12.dot(X);
  const double c3 = n12.dot(N3);
  const double scale = std::sqrt(e12.norm());  // ~ edge length
  double roots[3];
  const int nr = cubic_roots(c0, c1, c2, c3, scale, roots);

  NormalFit best;
  const double size = std::max({E1.norm(), E2.norm(), X.norm(), 1e-300});
  for (int k = 0; k < nr; ++k) {
    double h = roots[k];
    // Barycentrics at this height: x - c_h = u e1 + v e2 (least squares).
    Vec3 e1 = E1 + h * N1, e2 = E2 + h * N2;
    Vec3 r = X + h * N3;
    const double g11 = e1.dot(e1), g12 = e1.dot(e2), g22 = e2.dot(e2);
    const double det2 = g11 * g22 - g12 * g12;
    if (!(std::abs(det2) > 1e-30 * g11 * g22) || !std::isfinite(det2)) continue;
    double u = (g22 * e1.dot(r) - g12 * e2.dot(r)) / det2;
    double v = (g11 * e2.dot(r) - g12 * e1.dot(r)) / det2;
    // Clearly outside the triangle on a well-conditioned frame: Newton would only remove the
    // root's rounding, far less than this margin.
    if (det2 > 1e-6 * g11 * g22 && std::min({u, v, 1.0 - u - v}) < -tolerance - 0.01) continue;
    // Newton on F(u, v, h) (the cubic root is exact up to rounding; this removes it).
    for (int it = 0; it < 3; ++it) {
      e1 = E1 + h * N1;
      e2 = E2 + h * N2;
      const Vec3 nh = u * N1 + v * N2 - N3;  // interpolated normal u na + v nb + w nc
      const Vec3 f = u * e1 + v * e2 - (X + h * N3);
      Eigen::Matrix3d j;
      j << e1, e2, nh;
      const double dj = j.determinant();
      if (!(std::abs(dj) > 0.0)) break;
      const Vec3 step = j.inverse() * f;
      if (!step.allFinite()) break;
      u -= step[0];
      v -= step[1];
      h -= step[2];
    }
    const double w = 1.0 - u - v;
    if (!(u >= -tolerance && v >= -tolerance && w >= -tolerance) || !std::isfinite(h)) continue;
    const Vec3 rec = u * (a + h * na) + v * (b + h * nb) + w * (c + h * nc);
    if (!((rec - x).norm() <= 1e-9 * (size + std::abs(h)))) continue;
    if (best.ok && std::abs(h) >= std::abs(best.h)) continue;
    best = {true, u, v, w, h, offset_jacobian_det(a, b, c, na, nb, nc, u, v, w, h)};
  }
  return best;
}

double fit_height_lower_bound(const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, double tolerance) {
  const Vec3 nf = (b - a).cross(c - a);
  const double a2 = nf.squaredNorm();  // (twice the area)^2
  if (!(a2 > 0.0) || !std::isfinite(a2)) return 0.0;
  const double len = std::sqrt(a2);
  const double plane = std::abs((x - a).dot(nf)) / len;
  // Barycentrics of x's projection; beta_k = -tolerance is a line at distance (-tolerance - beta_k)
  // times the altitude from corner k.
  const double beta[3] = {nf.dot((c - b).cross(x - b)) / a2, nf.dot((a - c).cross(x - c)) / a2, 0.0};
  const double beta_c = 1.0 - beta[0] - beta[1];
  const double edge[3] = {(c - b).norm(), (a - c).norm(), (b - a).norm()};
  double in_plane = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double bk = k == 2 ? beta_c : beta[k];
    if (bk < -tolerance) in_plane = std::max(in_plane, (-tolerance - bk) * len / edge[k]);
  }
  const double dist = std::sqrt(plane * plane + in_plane * in_plane);
  // Slack for the fit's accepted residual (1e-9 of its size) and for rounding here.
  const double size = std::max({edge[0], edge[1], edge[2]}) + (x - c).norm();
  return std::max(0.0, (dist * (1.0 - 1e-6) - 1e-6 * size) / (1.0 + 4.0 * tolerance + 1e-6));
}

double safe_height(const JacobianRay& j, double h, double min_ratio) {
  if (!(j.a0 > 0.0)) return 0.0;
  const double floor = min_ratio * j.a0;
  if (j.at(h) >= floor) return h;
  // f(s) = det(s) - floor: f(0) > 0 >= f(h). Bisection on [0, h]: robust where the quadratic is
  // nearly linear, and 40 halvings reach rounding level of h.
  double lo = 0.0, hi = h;
  for (int i = 0; i < 40; ++i) {
    const double mid = 0.5 * (lo + hi);
    (j.at(mid) >= floor ? lo : hi) = mid;
  }
  return lo;
}

}  // namespace freeform::multires
