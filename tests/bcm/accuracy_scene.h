// The accuracy tests' scene (issue 13): the armadillo (libcgal-demo) subdivided twice to 416k
// vertices, a support of the first N + H vertices of a breadth-first order from vertex 1000
// (as bench/bench_bcm.cpp), the first H = max(50, N / 50) of them the handle, translated by
// (0.1, 0.2, 0.05) of the bounding-box diagonal. Compares BcmSolver with mixed_form_reference.
#pragma once

#include "mixed_reference.h"
#include "test_support.h"

#include "freeform/bcm/bcm_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace freeform::test {

struct AccuracyMesh {
  Mesh mesh;
  std::vector<Vertex> bfs;
  double diagonal = 0;
};

inline const AccuracyMesh& accuracy_mesh() {
  static const AccuracyMesh m = [] {
    AccuracyMesh a;
    a.mesh = Mesh::from_soup(subdivide_midpoint(subdivide_midpoint(read_mesh((cgal_mesh_dir() / "armadillo.off").string()).soup)));
    const Vertex seed[] = {Vertex(1000)};
    a.bfs = k_ring(a.mesh, seed, 100000);
    Vec3 lo = a.mesh.position(Vertex(0)), hi = lo;
    for (const Vec3& p : a.mesh.positions().raw()) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    a.diagonal = (hi - lo).norm();
    return a;
  }();
  return m;
}

struct AccuracyResult {
  double error = 0;  // max over free vertices of |solver - reference|, relative to the diagonal
  BcmStats stats;
};

inline AccuracyResult accuracy_at(int free_count, const BcmSettings& settings) {
  const AccuracyMesh& m = accuracy_mesh();
  const int h = std::max(50, free_count / 50);
  const std::vector<Vertex> handle(m.bfs.begin(), m.bfs.begin() + h);
  const std::vector<Vertex> support(m.bfs.begin(), m.bfs.begin() + h + free_count);
  const Regions regions(m.mesh, support, {HandleRegion{handle, true}});
  const Vec3 shift = Vec3(0.1, 0.2, 0.05) * m.diagonal;
  const BcmSolver solver(m.mesh, regions, settings);
  const Eigen::Affine3d t(Eigen::Translation3d{shift});
  BcmSolver::RowMatrixX3d ours(solver.n_free(), 3);
  solver.evaluate(std::span<const Eigen::Affine3d>(&t, 1), ours);
  VertexData<Vec3> boundary = m.mesh.positions();
  for (Vertex v : handle) boundary[v] += shift;
  const double k1 = settings.order - 1.0;
  const auto c = [&](double v) { return v == Smoothness::kDefault ? k1 : v; };
  const Eigen::MatrixXd ref =
      mixed_form_reference(m.mesh, regions, settings.order, boundary, c(settings.smoothness.outer), c(settings.smoothness.inner));
  double error = 0;  // the reference's rows follow regions.free_vertices(), ours the solver's order
  const std::vector<Vertex>& free = regions.free_vertices();
  std::vector<int> row_of(static_cast<std::size_t>(m.mesh.n_vertices()), -1);
  for (std::size_t i = 0; i < free.size(); ++i) row_of[static_cast<std::size_t>(free[i].idx())] = static_cast<int>(i);
  for (std::size_t i = 0; i < solver.free_vertices().size(); ++i)
    error = std::max(error, (ours.row(static_cast<Eigen::Index>(i)) -
                             ref.row(row_of[static_cast<std::size_t>(solver.free_vertices()[i].idx())])).norm());
  return {error / m.diagonal, solver.stats()};
}

}  // namespace freeform::test
