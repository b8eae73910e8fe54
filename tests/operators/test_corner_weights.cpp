// One corner-weight function (operators/face_geometry.h) serves the global operators and the
// local BCM assembly: on a grid with degenerate triangles (zero area, a needle, an angle near
// 180 degrees, a 1e-300 height) both give the same weights, areas and degenerate-face counts.
#include "freeform/bcm/bcm_system.h"
#include "freeform/mesh/generators.h"
#include "freeform/operators/face_geometry.h"
#include "freeform/operators/operators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

using namespace freeform;

TEST(CornerWeights, RightIsoscelesTriangleByHand) {
  const detail::CornerWeights w = detail::corner_weights(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));
  ASSERT_FALSE(w.degenerate);
  EXPECT_NEAR(w.cot[0], 0.0, 1e-15);  // the right angle
  EXPECT_NEAR(w.cot[1], 1.0, 1e-15);  // 45 degrees
  EXPECT_NEAR(w.cot[2], 1.0, 1e-15);
  EXPECT_NEAR(w.area[0], 0.25, 1e-15);  // (1 * cot 45 + 1 * cot 45) / 8
  EXPECT_NEAR(w.area[1], 0.125, 1e-15);  // (1 * cot 45 + 2 * cot 90) / 8
  EXPECT_NEAR(w.area[2], 0.125, 1e-15);
  // Obtuse: half the area to the obtuse corner, a quarter to the others.
  const detail::CornerWeights o = detail::corner_weights(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(1, 0.1, 0));
  EXPECT_NEAR(o.area[2], 0.05, 1e-15);
  EXPECT_NEAR(o.area[0], 0.025, 1e-15);
  EXPECT_TRUE(detail::corner_weights(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1e-300, 0)).degenerate);
  EXPECT_EQ(detail::corner_weights(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1e-9, 0)).clamped, 3);  // two needles, one ~180
}

TEST(CornerWeights, GlobalOperatorsAndLocalAssemblyAgreeOnDegenerateTriangles) {
  TriangleSoup soup = make_plane(12, 12);  // 13 x 13 vertices, spacing 1/12
  auto at = [](int i, int j) { return static_cast<std::size_t>(j * 13 + i); };
  soup.positions[at(4, 4)] = soup.positions[at(5, 4)];                       // zero area (repeated position)
  soup.positions[at(8, 5)] += Vec3(0.0, 0.5 / 12 - 1e-9, 0.0);              // a needle
  soup.positions[at(5, 8)] = 0.5 * (soup.positions[at(4, 8)] + soup.positions[at(6, 8)]) + Vec3(0, 1e-7, 0);  // ~180 degrees
  soup.positions[at(7, 7)].z() += 0.05;                                      // and some curvature
  const Mesh mesh = Mesh::from_soup(soup);

  OperatorDiagnostics global;
  const SparseMatrix L = cotan_laplacian(mesh, &global);
  const Eigen::VectorXd A = mixed_voronoi_areas(mesh, &global);
  for (int k = 0; k < L.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(L, k); it; ++it) ASSERT_TRUE(std::isfinite(it.value()));
  EXPECT_GT(global.degenerate_faces, 0);

  // Support: the inner 9 x 9 block; one movable handle at its centre.
  std::vector<Vertex> support;
  for (int j = 2; j <= 10; ++j)
    for (int i = 2; i <= 10; ++i) support.push_back(Vertex(static_cast<int>(at(i, j))));
  const Regions regions(mesh, support, {HandleRegion{{Vertex(static_cast<int>(at(6, 6)))}, true}});

  for (int order : {1, 2}) {
    BcmSettings s;
    s.order = order;
    const BcmSystem sys = assemble_bcm_system(mesh, mesh.positions(), regions, s);
    EXPECT_EQ(sys.degenerate_faces, global.degenerate_faces) << "all degenerate faces lie in the assembled patch";
    EXPECT_EQ(sys.zero_area_vertices, 0);
    // The same rows from the global operators: (-1)^k S_k with S_1 = L, S_2 = L D L.
    const Eigen::MatrixXd Ld = Eigen::MatrixXd(L);
    const Eigen::MatrixXd S = order == 1 ? Ld : Eigen::MatrixXd(Ld * (1.0 / (2.0 * A.array())).matrix().asDiagonal() * Ld);
    const double sign = order == 1 ? -1.0 : 1.0;
    const Eigen::MatrixXd app(sys.a_pp), apc(sys.a_pc);
    double scale = S.cwiseAbs().maxCoeff(), err = 0.0;
    for (std::size_t r = 0; r < sys.free.size(); ++r) {
      const int gi = sys.free[r].idx();
      for (std::size_t c = 0; c < sys.free.size(); ++c)
        err = std::max(err, std::abs(app(static_cast<int>(r), static_cast<int>(c)) - sign * S(gi, sys.free[c].idx())));
      for (std::size_t c = 0; c < sys.constrained.size(); ++c)
        err = std::max(err, std::abs(apc(static_cast<int>(r), static_cast<int>(c)) - sign * S(gi, sys.constrained[c].idx())));
    }
    EXPECT_LE(err, 1e-12 * scale) << "order " << order;
    EXPECT_GT(scale, 0.0);
  }
}
