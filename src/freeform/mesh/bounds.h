// The bounding-box diagonal: the length scale of tolerances and relative errors.
#pragma once

#include "freeform/mesh/mesh.h"

namespace freeform {

// Diagonal of the box around the finite positions; 1 when that is zero, empty or not finite,
// so dividing by it is always safe.
double bounding_diagonal(const VertexData<Vec3>& positions);

}  // namespace freeform
