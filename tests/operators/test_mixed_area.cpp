// Mixed Voronoi areas, D, the uniform Laplacian, boundary edges and the degenerate-face policy.
#include "soup_facts.h"

#include "freeform/mesh/generators.h"
#include "freeform/operators/operators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace freeform {
namespace {

TriangleSoup soup(std::vector<Vec3> p, std::vector<Tri> f) { return TriangleSoup{std::move(p), std::move(f)}; }

TEST(MixedAreas, SumToSurfaceAreaIncludingObtuseMeshes) {
  TriangleSoup disk = make_disk(6, 1.0);
  test::jitter_interior(disk, 0.05, 3);
  TriangleSoup plane = make_plane(9, 7, 1.0, 0.8);
  test::jitter_interior(plane, 0.04, 11);
  TriangleSoup skewed = make_plane(6, 6, 4.0, 0.5);  // every face has a ~83 degree and a ~97 degree corner
  for (const auto& [name, s] : {std::pair<std::string, TriangleSoup>{"icosphere3", make_icosphere(3, 2.0)},
                                {"jittered_disk", disk},
                                {"jittered_plane", plane},
                                {"skewed_plane", skewed},
                                {"annulus", make_annulus(0.3, 1.0, 4, 24)},
                                {"cylinder", make_cylinder(5, 12, 0.5, 2.0)},
                                {"bumpy_plane", make_bumpy_plane(12, 12, 0.1, 1.5)}}) {
    SCOPED_TRACE(name);
    const Mesh mesh = Mesh::from_soup(s);
    OperatorDiagnostics diag;
    const Eigen::VectorXd a = mixed_voronoi_areas(mesh, &diag);
    ASSERT_EQ(a.size(), mesh.n_vertices());
    const double total = test::surface_area(s);
    EXPECT_NEAR(a.sum(), total, 1e-13 * total);
    EXPECT_GT(a.minCoeff(), 0.0);
    EXPECT_EQ(diag.degenerate_faces, 0);
    EXPECT_EQ(diag.zero_area_vertices, 0);
  }
}

TEST(MixedAreas, KnownTrianglesByHand) {
  {  // Right isosceles, legs 1: Voronoi (non-obtuse): (1*cot45 + 1*cot45)/8 = 1/4 at the right
     // angle, (1*cot45 + 2*cot90)/8 = 1/8 at the others. (Barycentric would give 1/6 each.)
    const Eigen::VectorXd a =
        mixed_voronoi_areas(Mesh::from_soup(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}})));
    EXPECT_NEAR(a[0], 0.25, 1e-16);
    EXPECT_NEAR(a[1], 0.125, 1e-16);
    EXPECT_NEAR(a[2], 0.125, 1e-16);
  }
  {  // Obtuse at vertex 2, area 0.2: A/2 there, A/4 at the others.
    const Eigen::VectorXd a =
        mixed_voronoi_areas(Mesh::from_soup(soup({{0, 0, 0}, {2, 0, 0}, {1, 0.2, 0}}, {{0, 1, 2}})));
    EXPECT_NEAR(a[0], 0.05, 1e-16);
    EXPECT_NEAR(a[1], 0.05, 1e-16);
    EXPECT_NEAR(a[2], 0.10, 1e-16);
  }
  {  // Equilateral: a third each.
    const double h = std::sqrt(3.0) / 2.0;
    const Eigen::VectorXd a =
        mixed_voronoi_areas(Mesh::from_soup(soup({{0, 0, 0}, {1, 0, 0}, {0.5, h, 0}}, {{0, 1, 2}})));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], std::sqrt(3.0) / 12.0, 1e-16);
  }
}

TEST(MixedAreas, InverseDoubleAreas) {
  Eigen::VectorXd a(4);
  a << 0.25, 2.0, 0.0, 1e-3;
  const Eigen::VectorXd d = inverse_double_areas(a);
  EXPECT_DOUBLE_EQ(d[0], 2.0);
  EXPECT_DOUBLE_EQ(d[1], 0.25);
  EXPECT_EQ(d[2], 0.0);
  EXPECT_DOUBLE_EQ(d[3], 500.0);
}

TEST(UniformLaplacian, RowsSumToZeroDiagonalIsMinusValence) {
  for (const TriangleSoup& s : {make_icosphere(2), make_disk(4), make_plane(5, 3), make_cylinder(3, 7)}) {
    const Mesh mesh = Mesh::from_soup(s);
    const SparseMatrix U = uniform_laplacian(mesh);
    const auto nb = test::neighbours(s);
    ASSERT_EQ(U.rows(), static_cast<Eigen::Index>(s.positions.size()));
    EXPECT_EQ((U * Eigen::VectorXd::Ones(U.cols())).cwiseAbs().maxCoeff(), 0.0);
    EXPECT_EQ(SparseMatrix(U - SparseMatrix(U.transpose())).norm(), 0.0);
    for (int i = 0; i < U.rows(); ++i)
      EXPECT_EQ(U.coeff(i, i), -static_cast<double>(nb[static_cast<std::size_t>(i)].size()));
    for (int k = 0; k < U.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(U, k); it; ++it) {
        if (it.row() == it.col()) continue;
        EXPECT_EQ(it.value(), 1.0);
        EXPECT_TRUE(nb[static_cast<std::size_t>(it.row())].count(static_cast<int>(it.col())));
      }
    }
  }
}

TEST(BoundaryEdges, CountsByFormula) {
  auto count = [](const TriangleSoup& s) {
    const Mesh mesh = Mesh::from_soup(s);
    const std::vector<Edge> b = boundary_edges(mesh);
    for (std::size_t i = 0; i < b.size(); ++i) {
      EXPECT_TRUE(mesh.is_boundary(b[i]));
      if (i > 0) {
        EXPECT_LT(b[i - 1].idx(), b[i].idx());
      }
    }
    return static_cast<int>(b.size());
  };
  EXPECT_EQ(count(make_plane(4, 7)), 2 * (4 + 7));
  EXPECT_EQ(count(make_plane(1, 1)), 4);
  EXPECT_EQ(count(make_cylinder(3, 9)), 2 * 9);
  EXPECT_EQ(count(make_annulus(0.5, 1.0, 3, 17)), 2 * 17);
  EXPECT_EQ(count(make_disk(5)), 6 * 5);
  EXPECT_EQ(count(make_icosphere(2)), 0);
}

// Component A (vertices 0-4): a unit square fanned around vertex 4 on its bottom side, plus the
// zero-area face (0, 1, 4) closing the fan. Component B (5-7): a needle with 2A = 1e-7 and
// |cot| of 5e6, 5e6, -2.5e6. Components C (8-10, collinear) and D (11-13, coincident points):
// zero area; their vertices touch no other face.
TriangleSoup degenerate_soup() {
  return soup({{0, 0, 0},
               {1, 0, 0},
               {1, 1, 0},
               {0, 1, 0},
               {0.5, 0, 0},
               {3, 0, 0},
               {4, 0, 0},
               {3.5, 1e-7, 0},
               {10, 0, 0},
               {11, 0, 0},
               {12, 0, 0},
               {20, 0, 0},
               {20, 0, 0},
               {20, 0, 0}},
              {{0, 1, 4}, {0, 4, 3}, {4, 1, 2}, {4, 2, 3}, {5, 6, 7}, {8, 9, 10}, {11, 12, 13}});
}

TEST(Degenerate, FiniteOperatorsAndDiagnosticCounts) {
  const TriangleSoup s = degenerate_soup();
  const Mesh mesh = Mesh::from_soup(s);
  OperatorDiagnostics dl, da;
  const SparseMatrix L = cotan_laplacian(mesh, &dl);
  const Eigen::VectorXd a = mixed_voronoi_areas(mesh, &da);
  EXPECT_EQ(dl.degenerate_faces, 3);
  EXPECT_EQ(dl.clamped_cotangents, 3);
  EXPECT_EQ(da.degenerate_faces, 3);
  EXPECT_EQ(da.zero_area_vertices, 6);  // vertices 8-13

  const Eigen::MatrixXd Ld(L);
  EXPECT_TRUE(Ld.allFinite());
  EXPECT_EQ((Ld - Ld.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_LT((Ld.rowwise().sum()).cwiseAbs().maxCoeff(), 1e-9);
  // Needle: all three cotangents clamped to +-1e5, sign kept.
  EXPECT_EQ(Ld(5, 6), -1e5);  // opposite the ~180 degree corner
  EXPECT_EQ(Ld(5, 7), 1e5);
  EXPECT_EQ(Ld(6, 7), 1e5);
  // Degenerate components contribute nothing.
  EXPECT_EQ(Ld.bottomRows(6).cwiseAbs().maxCoeff(), 0.0);
  // The zero-area face adds nothing to edge 0-1 (boundary edge of that face only).
  EXPECT_EQ(Ld(0, 1), 0.0);
  // Face (0,4,3): cot 90 at 0, cot = 0.25/0.5 at 4, 1/0.5 at 3. Face (4,2,3): cot at 2 = 0.5/1.
  EXPECT_NEAR(Ld(0, 3), 0.5, 1e-15);  // opposite vertex 4
  EXPECT_NEAR(Ld(0, 4), 2.0, 1e-15);  // opposite vertex 3; the zero-area face adds nothing
  EXPECT_NEAR(Ld(4, 3), 0.5, 1e-15);  // cot 90 at 0 + cot at 2 in (4,2,3)

  EXPECT_TRUE(a.allFinite());
  EXPECT_GT(a.minCoeff(), 0.0);
  EXPECT_NEAR(a.head(5).sum(), 1.0, 1e-12);  // unit square
  EXPECT_NEAR(a.segment(5, 3).sum(), 0.5e-7, 1e-18);
  EXPECT_LT(a.tail(6).maxCoeff(), 1e-9);  // floored, tiny but positive
  const Eigen::VectorXd d = inverse_double_areas(a);
  EXPECT_TRUE(d.allFinite());
  const Eigen::VectorXd lap = d.asDiagonal() * (L * Eigen::VectorXd::LinSpaced(L.rows(), 0.0, 1.0));
  EXPECT_TRUE(lap.allFinite());
}

TEST(Degenerate, IsolatedVertexHasEmptyRowAndZeroArea) {
  const Mesh mesh = Mesh::from_soup(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {5, 5, 5}}, {{0, 1, 2}}));
  OperatorDiagnostics diag;
  const Eigen::MatrixXd L(cotan_laplacian(mesh, &diag));
  const Eigen::VectorXd a = mixed_voronoi_areas(mesh, &diag);
  EXPECT_EQ(L.row(3).cwiseAbs().sum(), 0.0);
  EXPECT_EQ(a[3], 0.0);
  EXPECT_EQ(inverse_double_areas(a)[3], 0.0);
  EXPECT_EQ(diag.zero_area_vertices, 0);
  EXPECT_EQ(diag.degenerate_faces, 0);
  EXPECT_EQ(uniform_laplacian(mesh).coeff(3, 3), 0.0);
}

}  // namespace
}  // namespace freeform
