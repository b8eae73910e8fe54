// Uniform (graph) Laplacian and the list of mesh-boundary edges.
#include "freeform/operators/operators.h"

namespace freeform {

SparseMatrix uniform_laplacian(const Mesh& mesh) {
  return laplacian_from_edge_weights(mesh, EdgeData<double>(static_cast<std::size_t>(mesh.n_edges()), 1.0));
}

std::vector<Edge> boundary_edges(const Mesh& mesh) {
  std::vector<Edge> out;
  for (Edge e : mesh.edges()) {
    if (mesh.is_boundary(e)) out.push_back(e);
  }
  return out;
}

}  // namespace freeform
