// The planar domain of anisotropic bending (docs/anisotropic.md): the support grown by k
// rings, mapped conformally to the plane (LSCM), rotated to its area-weighted principal axes
// and scaled so that both principal extents are equal. Cotangents and mixed areas computed on
// these positions (z = 0) replace the 3D ones in the BCM operator (sections 2-3).
#pragma once

#include "freeform/mesh/mesh.h"

#include <array>
#include <span>
#include <string>

namespace freeform {

struct AnisotropicDomain {
  bool used = false;        // false: use the isotropic (3D) operator; `fallback` says why
  std::string fallback;     // empty when used
  // #V positions: (s1 q1, s2 q2, 0) on the patch (q: principal-axis coordinates of the
  // conformal map), the mesh positions elsewhere. Empty when not used.
  VertexData<Vec3> positions;
  // Principal extents (major, minor) of the conformal map before the equalizing scale, in mesh
  // units (the map is scaled to the 3D area of the patch); of the largest component if the
  // patch has several. Set whenever the map was computed, also when a flip forced a fallback.
  std::array<double, 2> extents{0.0, 0.0};
  int patch_vertices = 0, patch_faces = 0, components = 0;
  int genus = 0;            // summed over the components of the patch
  int flipped = 0;          // flipped parameter triangles (fallback if > 0)
  double angle_distortion_max = 0.0;  // of the conformal map (sigma1 / sigma2 - 1)
  double ms = 0.0;          // wall time of the whole step
};

// `support`: the support vertices (free and handle), `k`: the order (domain = k rings around
// the support). Never throws for a topological reason: genus > 0, a closed component, a patch
// that is not manifold (two fans of faces meeting at one vertex) or flipped parameter triangles
// give used = false with the reason in `fallback`. Each connected component of the patch is
// mapped on its own. Throws InvalidInput for a vertex outside the mesh or k < 1.
AnisotropicDomain anisotropic_domain(const Mesh& mesh, std::span<const Vertex> support, int k);

}  // namespace freeform
