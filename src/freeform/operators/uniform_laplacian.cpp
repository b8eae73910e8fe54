// Uniform (graph) Laplacian and the list of mesh-boundary edges.
#include "freeform/operators/operators.h"

namespace freeform {

SparseMatrix uniform_laplacian(const Mesh& mesh) {
  const int n = mesh.n_vertices();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(2 * static_cast<std::size_t>(mesh.n_edges()) + static_cast<std::size_t>(n));
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  for (Edge e : mesh.edges()) {
    const int i = mesh.to_vertex(mesh.halfedge(e, 0)).idx();
    const int j = mesh.to_vertex(mesh.halfedge(e, 1)).idx();
    triplets.emplace_back(i, j, 1.0);
    triplets.emplace_back(j, i, 1.0);
    diagonal[i] -= 1.0;
    diagonal[j] -= 1.0;
  }
  for (int i = 0; i < n; ++i) triplets.emplace_back(i, i, diagonal[i]);
  SparseMatrix U(n, n);
  U.setFromTriplets(triplets.begin(), triplets.end());
  return U;
}

std::vector<Edge> boundary_edges(const Mesh& mesh) {
  std::vector<Edge> out;
  for (Edge e : mesh.edges()) {
    if (mesh.is_boundary(e)) out.push_back(e);
  }
  return out;
}

}  // namespace freeform
