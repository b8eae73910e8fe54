// Real roots of a cubic, for the normal-displacement fit (multires) and the volume multiplier
// (nonlinear).
#pragma once

namespace freeform {

// Real roots of c3 h^3 + c2 h^2 + c1 h + c0 = 0 (degree drops when leading coefficients are
// negligible at the length scale `scale`), each polished by Newton steps. Writes up to 3
// roots, returns their count.
int cubic_roots(double c0, double c1, double c2, double c3, double scale, double roots[3]);

}  // namespace freeform
