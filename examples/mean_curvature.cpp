// Example: load a mesh and print the range of its discrete mean curvature
// |Lap(x)| / 2 = |D L x| / 2 (docs/operators.md). Usage: mean_curvature MESH
#include "freeform/common/error.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"
#include "freeform/operators/operators.h"

#include <cstdio>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s MESH\n", argv[0]);
    return 2;
  }
  try {
    const freeform::Mesh mesh = freeform::Mesh::from_soup(freeform::read_mesh(argv[1]).soup);
    const Eigen::MatrixX3d x = mesh.position_matrix();
    const Eigen::VectorXd d = freeform::inverse_double_areas(freeform::mixed_voronoi_areas(mesh));
    const Eigen::MatrixX3d lap = d.asDiagonal() * (freeform::cotan_laplacian(mesh) * x);
    const Eigen::VectorXd h = lap.rowwise().norm() / 2;
    std::printf("%d vertices, mean curvature in [%g, %g], mean %g\n", mesh.n_vertices(), h.minCoeff(),
                h.maxCoeff(), h.mean());
  } catch (const freeform::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
