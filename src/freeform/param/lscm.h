// Least squares conformal maps (Levy, Petitjean, Ray, Maillot 2002) of a triangle-mesh patch,
// and the flip / distortion measures used to judge a parametrization (docs/anisotropic.md).
//
// Energy: sum over faces t of A_t |grad v - R90 grad u|^2 (the Cauchy-Riemann residual in a
// local orthonormal frame of t, R90 = rotation by +90 degrees), minimised with two pinned
// boundary vertices; the normal equations are symmetric positive definite and go to the
// project's SparseSolver (CHOLMOD when available).
#pragma once

#include "freeform/mesh/mesh.h"

#include <Eigen/Core>

#include <array>
#include <span>
#include <vector>

namespace freeform {

using Vec2 = Eigen::Vector2d;

// Topology of a mesh (or patch): Euler characteristic chi = V - E + F = 2 - 2g - b per
// connected component. genus is the sum over components (isolated vertices ignored).
struct PatchTopology {
  int components = 0;
  int boundary_loops = 0;
  int genus = 0;
};
PatchTopology patch_topology(const Mesh& mesh);

// Quality of a parametrization uv (#V entries) of `mesh`. Faces degenerate in 3D are skipped.
struct ParamDistortion {
  int flipped = 0;                    // faces with signed uv area <= 0 (orientation reversed)
  int degenerate = 0;                 // faces degenerate in 3D (not measured)
  double angle_max = 0.0;             // max over faces of sigma1 / sigma2 - 1 (0: conformal)
  double angle_mean = 0.0;            // the same, mean weighted by 3D area
  double area_max = 0.0;              // max over faces of |ln(A_uv / (s A_3d))|, s = total uv
  double area_mean = 0.0;             //   area / total 3D area (0: isometric up to scale)
};
ParamDistortion measure_distortion(const Mesh& mesh, std::span<const Vec2> uv);

// The flip detector alone: indices of the faces whose uv triangle has signed area <= 0
// (faces degenerate in 3D are not reported). uv: #V entries.
std::vector<Face> flipped_faces(const Mesh& mesh, std::span<const Vec2> uv);

struct LscmResult {
  std::vector<Vec2> uv;           // #V parameter positions, scaled so the uv area = 3D area
  std::array<Vertex, 2> pins;     // the two pinned boundary vertices (far apart in 3D)
  ParamDistortion distortion;     // flips and angle / area distortion of uv
};

// LSCM of a connected patch with at least one boundary loop and genus 0 (one or several
// boundary loops). Pins: the boundary vertex farthest from boundary vertex 0 and the one
// farthest from it. Cost: one sparse Cholesky of size 2(#V - 2).
// Throws InvalidInput (empty mesh, isolated vertices, several components, no boundary,
// non-finite positions), TopologyError (genus > 0, naming it), SolverError (factorization).
LscmResult lscm(const Mesh& patch);

}  // namespace freeform
