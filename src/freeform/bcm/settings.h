// Parameters of a BCM edit (DESIGN.md sections 1 and 3).
#pragma once

#include "freeform/mesh/handles.h"
#include "freeform/numerics/solver_kind.h"

#include <utility>
#include <vector>

namespace freeform {

// Boundary smoothness c in [0, k-1] per constrained vertex: c = 0 is C0 (a crease),
// c = k-1 full C^(k-1). Negative outer/inner mean "k-1" (the default).
struct Smoothness {
  double outer = -1.0;  // fixed vertices (outside the support)
  double inner = -1.0;  // handle vertices (movable and immovable)
  std::vector<std::pair<Vertex, double>> overrides;  // per constrained vertex, wins over outer/inner
};

// lambda_m(c) = clamp(c - m + 1, 0, 1): the weight of the level-m Laplacian at a stencil vertex
// (DESIGN.md section 3, the continuous form that fixes the paper's typo).
double smoothness_lambda(double c, int m);

struct BcmSettings {
  int order = 2;  // k: 1 membrane, 2 thin plate, 3 minimal curvature variation
  Smoothness smoothness;
  SolverKind solver = SolverKind::Auto;  // Auto: by the symmetry check (section 3)
};

// Throws InvalidInput naming the value: order not in {1,2,3}, smoothness outside [0, k-1]
// or not finite.
void validate_settings(const BcmSettings& settings);

}  // namespace freeform
