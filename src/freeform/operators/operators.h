// Discrete differential operators on triangle meshes (DESIGN.md section 2).
//
// Lap(x)_i = 1/(2 A_i) * sum_j (cot a_ij + cot b_ij) (x_j - x_i) = (D L x)_i with
//   L  #V by #V symmetric, L_ij = cot a_ij + cot b_ij (one cot for a mesh-boundary edge),
//      L_ii = -sum_j L_ij (rows sum to zero, negative semi-definite);
//   A  mixed Voronoi areas (Meyer et al. 2003), D = diag(1 / (2 A_i)).
// Degenerate triangles never produce inf/NaN; what was clamped is counted in the diagnostics.
#pragma once

#include "freeform/mesh/mesh.h"

#include <Eigen/SparseCore>

#include <vector>

namespace freeform {

using SparseMatrix = Eigen::SparseMatrix<double>;

struct OperatorDiagnostics {
  int degenerate_faces = 0;     // (near) zero area: contribute neither weights nor area
  int clamped_cotangents = 0;   // |cot| above the clamp on a non-degenerate face
  int zero_area_vertices = 0;   // non-isolated vertices whose area was floored to stay positive
};

// Positions override (e.g. a parametrization embedded in z = 0) must have #V entries.
SparseMatrix cotan_laplacian(const Mesh& mesh, OperatorDiagnostics* diag = nullptr);
SparseMatrix cotan_laplacian(const Mesh& mesh, const VertexData<Vec3>& positions, OperatorDiagnostics* diag = nullptr);

// #V mixed Voronoi areas; they sum to the surface area. Isolated vertices get 0.
Eigen::VectorXd mixed_voronoi_areas(const Mesh& mesh, OperatorDiagnostics* diag = nullptr);
Eigen::VectorXd mixed_voronoi_areas(const Mesh& mesh, const VertexData<Vec3>& positions,
                                    OperatorDiagnostics* diag = nullptr);

// The diagonal of D = diag(1 / (2 A_i)) (0 for isolated vertices).
Eigen::VectorXd inverse_double_areas(const Eigen::VectorXd& areas);

// Uniform (graph) Laplacian: U_ij = 1 for neighbours, U_ii = -valence.
SparseMatrix uniform_laplacian(const Mesh& mesh);

// Edges on the mesh boundary (one face only), in edge index order.
std::vector<Edge> boundary_edges(const Mesh& mesh);

}  // namespace freeform
