#include "freeform/numerics/cubic.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace freeform {
namespace {

// c3 t^3 + c2 t^2 + c1 t + c0 in the scaled variable t (coefficients of comparable size).
double poly(const double c[4], double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }
double dpoly(const double c[4], double t) { return (3.0 * c[3] * t + 2.0 * c[2]) * t + c[1]; }

void polish(const double c[4], double& t) {
  for (int it = 0; it < 3; ++it) {
    const double d = dpoly(c, t);
    if (d == 0.0) return;
    const double step = poly(c, t) / d;
    if (!std::isfinite(step)) return;
    t -= step;
  }
}

}  // namespace

int cubic_roots(double c0, double c1, double c2, double c3, double scale, double roots[3]) {
  // Work in t = h / scale so that a negligible leading coefficient is recognizable.
  const double s = scale > 0.0 ? scale : 1.0;
  double c[4] = {c0, c1 * s, c2 * s * s, c3 * s * s * s};
  const double m = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2]), std::abs(c[3])});
  if (!(m > 0.0) || !std::isfinite(m)) return 0;
  for (double& ci : c) ci /= m;
  constexpr double kNegligible = 1e-9;
  int n = 0;
  double t[3];
  if (std::abs(c[3]) > kNegligible) {
    const double a = c[2] / c[3], b = c[1] / c[3], d = c[0] / c[3];
    const double p = b - a * a / 3.0;
    const double q = 2.0 * a * a * a / 27.0 - a * b / 3.0 + d;
    const double disc = q * q / 4.0 + p * p * p / 27.0;
    if (disc > 0.0) {
      const double sq = std::sqrt(disc);
      t[n++] = std::cbrt(-q / 2.0 + sq) + std::cbrt(-q / 2.0 - sq) - a / 3.0;
    } else if (p == 0.0) {
      t[n++] = -a / 3.0;
    } else {
      const double r = 2.0 * std::sqrt(-p / 3.0);
      const double arg = std::clamp(3.0 * q / (p * r), -1.0, 1.0);
      const double phi = std::acos(arg) / 3.0;
      for (int k = 0; k < 3; ++k) t[n++] = r * std::cos(phi - 2.0 * std::numbers::pi * k / 3.0) - a / 3.0;
    }
  } else if (std::abs(c[2]) > kNegligible) {
    const double disc = c[1] * c[1] - 4.0 * c[2] * c[0];
    if (disc >= 0.0) {
      const double qq = -0.5 * (c[1] + std::copysign(std::sqrt(disc), c[1]));
      t[n++] = qq / c[2];
      if (qq != 0.0) t[n++] = c[0] / qq;
    }
  } else if (std::abs(c[1]) > kNegligible) {
    t[n++] = -c[0] / c[1];
  }
  int out = 0;
  for (int k = 0; k < n; ++k) {
    polish(c, t[k]);
    if (std::isfinite(t[k])) roots[out++] = t[k] * s;
  }
  return out;
}

}  // namespace freeform
