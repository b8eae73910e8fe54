// Parameters of a BCM edit (docs/bcm.md).
#pragma once

#include "freeform/mesh/handles.h"
#include "freeform/numerics/solver_kind.h"

#include <vector>

namespace freeform {

// A stretch of the boundary with its own smoothness (the paper's piecewise boundary
// conditions, Fig. 5): `value` on each of `vertices`. Free vertices in the list are ignored.
struct SmoothnessSegment {
  std::vector<Vertex> vertices;
  double value = 0.0;
  bool operator==(const SmoothnessSegment&) const = default;
};

// Boundary smoothness c in [0, k-1] per constrained vertex: c = 0 is C0 (a crease),
// c = k-1 full C^(k-1). outer/inner equal to kDefault (-1) mean "k-1" (the default); any other
// value outside [0, k-1] is refused by validate_settings. Segments win over outer/inner, later
// segments over earlier ones; free vertices always have c = k-1.
struct Smoothness {
  static constexpr double kDefault = -1.0;
  double outer = kDefault;  // fixed vertices (outside the support)
  double inner = kDefault;  // handle vertices (movable and immovable)
  std::vector<SmoothnessSegment> segments;
  bool operator==(const Smoothness&) const = default;
};

// lambda_m(c) = clamp(c - m + 1, 0, 1): the weight of the level-m Laplacian at a stencil vertex
// (docs/bcm.md, the continuous form that fixes the paper's typo).
double smoothness_lambda(double c, int m);

struct BcmSettings {
  int order = 2;  // k: 1 membrane, 2 thin plate, 3 minimal curvature variation
  Smoothness smoothness;
  SolverKind solver = SolverKind::Auto;  // Auto: by the symmetry check (section 3)
  // Anisotropic bending (section 5, docs/anisotropic.md): cotangents and areas from the
  // equalized conformal map of the support grown by k rings; falls back to the isotropic
  // operator (reason in BcmStats) for genus > 0 or flipped parameter triangles.
  bool anisotropic = false;
  bool operator==(const BcmSettings&) const = default;
};

// Throws InvalidInput naming the value: order not in {1,2,3}, smoothness outside [0, k-1]
// (other than the kDefault sentinel for outer/inner) or not finite, a segment naming an
// invalid vertex handle.
void validate_settings(const BcmSettings& settings);

// outer/inner with kDefault resolved to k-1 (before segments).
double resolved_outer(const BcmSettings& settings);
double resolved_inner(const BcmSettings& settings);

}  // namespace freeform
