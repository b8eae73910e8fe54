// Cotangent Laplacian L (docs/operators.md): L_ij = cot a_ij + cot b_ij, L_ii = -sum_j L_ij.
#include "freeform/common/error.h"
#include "freeform/operators/face_geometry.h"
#include "freeform/operators/operators.h"

#include <cmath>
#include <string>

namespace freeform {

namespace detail {

void check_positions(const Mesh& mesh, const VertexData<Vec3>& positions, const char* function) {
  if (positions.size() != static_cast<std::size_t>(mesh.n_vertices())) {
    throw InvalidInput(std::string(function) + ": positions have " + std::to_string(positions.size()) +
                       " entries but the mesh has " + std::to_string(mesh.n_vertices()) + " vertices");
  }
  for (const Vec3& p : positions) {
    if (!p.allFinite()) throw InvalidInput(std::string(function) + ": positions contain a non-finite coordinate");
  }
}

}  // namespace detail

namespace {

// Per face: three cotangents added to the edges opposite their corners (positions checked).
EdgeData<double> accumulate_weights(const Mesh& mesh, const VertexData<Vec3>& positions, OperatorDiagnostics* diag) {
  EdgeData<double> weight(static_cast<std::size_t>(mesh.n_edges()), 0.0);
  int degenerate = 0;
  int clamped = 0;
  for (Face f : mesh.faces()) {
    const detail::FaceCorners c = detail::face_corners(mesh, f);
    const detail::CornerWeights w = detail::corner_weights(positions[c.v[0]], positions[c.v[1]], positions[c.v[2]]);
    degenerate += w.degenerate ? 1 : 0;
    clamped += w.clamped;
    for (std::size_t k = 0; k < 3; ++k) weight[mesh.edge(c.h[k])] += w.cot[k];
  }
  if (diag) {
    diag->degenerate_faces = degenerate;
    diag->clamped_cotangents = clamped;
  }
  return weight;
}

}  // namespace

EdgeData<double> cotan_weights(const Mesh& mesh, const VertexData<Vec3>& positions, OperatorDiagnostics* diag) {
  detail::check_positions(mesh, positions, "cotan_weights");
  return accumulate_weights(mesh, positions, diag);
}

EdgeData<double> cotan_weights(const Mesh& mesh, OperatorDiagnostics* diag) {
  return accumulate_weights(mesh, mesh.positions(), diag);
}

SparseMatrix laplacian_from_edge_weights(const Mesh& mesh, const EdgeData<double>& weight) {
  // One triplet per edge and direction (edges are unique) plus the diagonal: no duplicates,
  // and every mesh edge is a structural entry even where its weight is 0.
  const int n = mesh.n_vertices();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(2 * static_cast<std::size_t>(mesh.n_edges()) + static_cast<std::size_t>(n));
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  for (Edge e : mesh.edges()) {
    const int i = mesh.to_vertex(mesh.halfedge(e, 0)).idx();
    const int j = mesh.to_vertex(mesh.halfedge(e, 1)).idx();
    const double w = weight[e];
    triplets.emplace_back(i, j, w);
    triplets.emplace_back(j, i, w);
    diagonal[i] -= w;
    diagonal[j] -= w;
  }
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, diagonal[i]);

  SparseMatrix L(n, n);
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

SparseMatrix cotan_laplacian(const Mesh& mesh, const VertexData<Vec3>& positions, OperatorDiagnostics* diag) {
  detail::check_positions(mesh, positions, "cotan_laplacian");
  return laplacian_from_edge_weights(mesh, accumulate_weights(mesh, positions, diag));
}

SparseMatrix cotan_laplacian(const Mesh& mesh, OperatorDiagnostics* diag) {
  return cotan_laplacian(mesh, mesh.positions(), diag);
}

}  // namespace freeform
