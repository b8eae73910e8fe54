// Generated surfaces for the parametrization and anisotropic-bending tests: developable
// pieces (cylinder, truncated cone), a spherical cap, a torus.
#pragma once

#include "freeform/mesh/generators.h"
#include "freeform/mesh/types.h"

#include <cmath>
#include <numbers>

namespace freeform::test {

// Grid (nu x nv quads) over (s, t) in [0,1]^2 mapped by f(s, t) -> Vec3; split along
// alternating diagonals; counter-clockwise in (s, t).
template <class F>
TriangleSoup grid_surface(int nu, int nv, F f, bool wrap_u = false, bool wrap_v = false) {
  TriangleSoup soup;
  const int cu = wrap_u ? nu : nu + 1, cv = wrap_v ? nv : nv + 1;
  for (int j = 0; j < cv; ++j)
    for (int i = 0; i < cu; ++i) soup.positions.push_back(f(static_cast<double>(i) / nu, static_cast<double>(j) / nv));
  const auto id = [&](int i, int j) { return (j % cv) * cu + (i % cu); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if ((i + j) % 2 == 0) {
        soup.faces.push_back({a, b, c});
        soup.faces.push_back({a, c, d});
      } else {
        soup.faces.push_back({a, b, d});
        soup.faces.push_back({b, c, d});
      }
    }
  return soup;
}

// Piece of a cylinder of radius r: angle in [0, span], height in [0, h]. Every grid quad is a
// planar rectangle, so the polyhedral surface unrolls isometrically.
inline TriangleSoup cylinder_piece(int nu, int nv, double r = 1.0, double span = 0.75 * std::numbers::pi, double h = 1.0) {
  return grid_surface(nu, nv, [=](double s, double t) { return Vec3(r * std::cos(span * s), r * std::sin(span * s), h * t); });
}

// Truncated cone with apex at the origin, half-angle alpha: slant distance in [d0, d1], angle
// in [0, span]. Quads span two rulings (planar trapezoids): developable.
inline TriangleSoup cone_piece(int nu, int nv, double alpha = 0.5, double d0 = 0.5, double d1 = 1.5,
                               double span = std::numbers::pi) {
  return grid_surface(nu, nv, [=](double s, double t) {
    const double d = d0 + (d1 - d0) * t, th = span * s;
    return Vec3(d * std::sin(alpha) * std::cos(th), d * std::sin(alpha) * std::sin(th), d * std::cos(alpha));
  });
}

// Torus (major radius R, minor r) with nu x nv quads, closed, genus 1, outward normals.
inline TriangleSoup torus(int nu, int nv, double big_r = 1.0, double r = 0.4) {
  return grid_surface(
      nu, nv,
      [=](double s, double t) {
        const double u = 2 * std::numbers::pi * s, v = 2 * std::numbers::pi * t;
        return Vec3((big_r + r * std::cos(v)) * std::cos(u), (big_r + r * std::cos(v)) * std::sin(u), r * std::sin(v));
      },
      true, true);
}

// make_disk lifted onto a sphere of radius `sphere` (a cap; curved, not developable).
inline TriangleSoup spherical_cap(int rings, double radius, double sphere) {
  TriangleSoup soup = make_disk(rings, radius);
  for (Vec3& p : soup.positions) p.z() = std::sqrt(sphere * sphere - p.head<2>().squaredNorm());
  return soup;
}

}  // namespace freeform::test
