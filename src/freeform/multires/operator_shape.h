// The shape multiresolution's base operator is discretized on (docs/multires.md, "Why the
// detail used to tear"). Cotangents and areas of the detailed mesh carry the detail's metric:
// under a tall bump the plate is "longer", so the smooth base bends sharply right there and
// the bump's tip, displaced along the base normals, folds. Here every free vertex is moved
// along the normal of a membrane fill (k = 1) of the support onto that fill's tangent plane,
// i.e. to the foot of its detail: the base keeps the mesh's tangential layout but loses the
// detail's height, so the bend follows the smooth shape.
#pragma once

#include "freeform/bcm/settings.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <string>

namespace freeform {

struct OperatorShape {
  VertexData<Vec3> positions;  // #V: foot points on the free vertices, the mesh elsewhere; empty if not used
  std::string fallback;        // why the detailed mesh's own shape is used instead (empty if used)
  int overhanging = 0;         // triangles whose foot points fold or are squeezed (the detail overhangs its base)
  int lifted_boundary = 0;     // free vertices on the mesh's open boundary the fill leaves along its normal
  double ms = 0;               // wall time (the membrane fill's factorization dominates)
};

// Empty positions with a reason when the foot points fold a triangle or squeeze it below a
// quarter in some direction (detail that overhangs its base, as on the armadillo's ear or
// fandisk's walls, or as tall as its base is wide, as a long tube over its pinched membrane) or with
// settings.anisotropic (that operator has its own domain).
// Also counts the free vertices on the mesh's open boundary that the fill leaves along its
// normal (lifted_boundary): the fill's boundary is free there and curls away from a curved
// surface, so the decomposition would invent detail at the boundary (a flat plane's sides stay
// on it).
OperatorShape base_operator_shape(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                                  const Progress& progress = {});

}  // namespace freeform
