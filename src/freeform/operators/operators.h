// Discrete differential operators on triangle meshes (docs/operators.md).
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

// Degenerate-face policy (docs/operators.md): a face with 2 * area <= 1e-12 * (longest edge)^2
// is degenerate and contributes neither weights nor area; on the other faces |cot| is clamped
// to 1e5 (negative cotangents of obtuse corners are kept). Each function below overwrites only
// the fields it computes: cotan_* set degenerate_faces and clamped_cotangents,
// mixed_voronoi_areas sets degenerate_faces and zero_area_vertices.
struct OperatorDiagnostics {
  int degenerate_faces = 0;    // (near) zero area: contribute neither weights nor area
  int clamped_cotangents = 0;  // |cot| above the clamp on a non-degenerate face
  int zero_area_vertices = 0;  // non-isolated vertices whose area was floored to stay positive
};

// Positions override (e.g. a parametrization embedded in z = 0) must have #V finite entries
// (InvalidInput otherwise). Every mesh edge is a structural entry of L, even with weight 0.
SparseMatrix cotan_laplacian(const Mesh& mesh, OperatorDiagnostics* diag = nullptr);
SparseMatrix cotan_laplacian(const Mesh& mesh, const VertexData<Vec3>& positions, OperatorDiagnostics* diag = nullptr);

// #E edge weights cot a_e + cot b_e (one cot for a boundary edge): the off-diagonal of L.
EdgeData<double> cotan_weights(const Mesh& mesh, OperatorDiagnostics* diag = nullptr);
EdgeData<double> cotan_weights(const Mesh& mesh, const VertexData<Vec3>& positions,
                               OperatorDiagnostics* diag = nullptr);

// #V mixed Voronoi areas; they sum to the surface area (of the non-degenerate faces).
// Isolated vertices get 0; other vertices with area below 1e-12 * (mean vertex area) are
// floored to that value and counted in zero_area_vertices, so 1 / (2 A_i) stays finite.
Eigen::VectorXd mixed_voronoi_areas(const Mesh& mesh, OperatorDiagnostics* diag = nullptr);
Eigen::VectorXd mixed_voronoi_areas(const Mesh& mesh, const VertexData<Vec3>& positions,
                                    OperatorDiagnostics* diag = nullptr);

// The diagonal of D = diag(1 / (2 A_i)) (0 where A_i == 0, i.e. isolated vertices).
Eigen::VectorXd inverse_double_areas(const Eigen::VectorXd& areas);

// L_ij = w_ij for every edge, L_ii = -sum_j w_ij (#V by #V, symmetric; every edge is stored).
SparseMatrix laplacian_from_edge_weights(const Mesh& mesh, const EdgeData<double>& weights);

// Uniform (graph) Laplacian: U_ij = 1 for neighbours, U_ii = -valence.
SparseMatrix uniform_laplacian(const Mesh& mesh);

// Edges on the mesh boundary (one face only), in edge index order.
std::vector<Edge> boundary_edges(const Mesh& mesh);

}  // namespace freeform
