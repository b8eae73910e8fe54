// Cotangent Laplacian: invariants (L 1 = 0, symmetry, negative semi-definite, linear
// precision) and hand-computed weights of known triangles.
#include "soup_facts.h"

#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"
#include "freeform/operators/operators.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <string>

namespace freeform {
namespace {

struct Case {
  std::string name;
  TriangleSoup soup;
};

TriangleSoup jittered_plane() {
  TriangleSoup s = make_plane(9, 7, 1.0, 0.8);
  test::jitter_interior(s, 0.04, 11);  // cell size ~0.11: faces stay positive, many obtuse
  return s;
}

TriangleSoup jittered_disk() {
  TriangleSoup s = make_disk(6, 1.0);
  test::jitter_interior(s, 0.05, 3);
  return s;
}

std::vector<Case> cases() {
  return {{"icosphere2", make_icosphere(2, 1.3)},       {"jittered_plane", jittered_plane()},
          {"jittered_disk", jittered_disk()},           {"annulus", make_annulus(0.3, 1.0, 4, 24)},
          {"cylinder", make_cylinder(5, 12, 0.5, 2.0)}, {"bumpy_plane", make_bumpy_plane(12, 12, 0.1, 1.5)}};
}

int count_obtuse(const TriangleSoup& s) {
  int n = 0;
  for (const Tri& t : s.faces) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = test::corner(s, t, k);
      if ((test::corner(s, t, (k + 1) % 3) - p).dot(test::corner(s, t, (k + 2) % 3) - p) < 0) ++n;
    }
  }
  return n;
}

double max_abs(const SparseMatrix& m) {
  double v = 0;
  for (int k = 0; k < m.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(m, k); it; ++it) v = std::max(v, std::abs(it.value()));
  return v;
}

TEST(CotanLaplacian, RowsSumToZeroAndSymmetric) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Mesh mesh = Mesh::from_soup(c.soup);
    OperatorDiagnostics diag;
    const SparseMatrix L = cotan_laplacian(mesh, &diag);
    ASSERT_EQ(L.rows(), mesh.n_vertices());
    ASSERT_EQ(L.cols(), mesh.n_vertices());
    const double scale = max_abs(L);
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(L.cols());
    EXPECT_LT((L * ones).cwiseAbs().maxCoeff(), 1e-13 * scale);
    EXPECT_EQ(SparseMatrix(L - SparseMatrix(L.transpose())).norm(), 0.0);
    EXPECT_EQ(diag.degenerate_faces, 0);
    EXPECT_EQ(diag.clamped_cotangents, 0);
    // Structure: the diagonal plus both directions of every edge.
    EXPECT_EQ(L.nonZeros(),
              static_cast<Eigen::Index>(c.soup.positions.size() + 2 * test::undirected_edges(c.soup).size()));
    // Off-diagonal entries only between soup neighbours.
    const auto nb = test::neighbours(c.soup);
    for (int k = 0; k < L.outerSize(); ++k) {
      for (SparseMatrix::InnerIterator it(L, k); it; ++it) {
        if (it.row() != it.col()) {
          EXPECT_TRUE(nb[static_cast<std::size_t>(it.row())].count(static_cast<int>(it.col())));
        }
      }
    }
  }
}

TEST(CotanLaplacian, NegativeSemiDefinite) {
  for (const Case& c : {Case{"icosphere1", make_icosphere(1)}, Case{"jittered_disk", jittered_disk()},
                        Case{"jittered_plane", jittered_plane()}, Case{"bumpy", make_bumpy_plane(8, 8, 0.2, 1.0)}}) {
    SCOPED_TRACE(c.name);
    const Mesh mesh = Mesh::from_soup(c.soup);
    const SparseMatrix L = cotan_laplacian(mesh);
    const Eigen::MatrixXd dense(L);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(dense, Eigen::EigenvaluesOnly);
    const double lmax = es.eigenvalues().maxCoeff();
    const double lmin = es.eigenvalues().minCoeff();
    EXPECT_LT(lmin, 0.0);
    EXPECT_LE(lmax, 1e-12 * std::abs(lmin));
    // Exactly one zero eigenvalue per connected component (all connected here).
    int zeros = 0;
    for (Eigen::Index i = 0; i < es.eigenvalues().size(); ++i)
      zeros += std::abs(es.eigenvalues()[i]) < 1e-10 * std::abs(lmin);
    EXPECT_EQ(zeros, 1);
    std::mt19937 rng(5);
    std::normal_distribution<double> g;
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd x(L.cols());
      for (Eigen::Index i = 0; i < x.size(); ++i) x[i] = g(rng);
      EXPECT_LE(x.dot(L * x), 1e-12 * x.squaredNorm() * std::abs(lmin));
    }
  }
}

// On a planar mesh, sum_j w_ij (x_j - x_i) = 0 at every interior vertex for any linear function,
// obtuse triangles included.
void expect_linear_precision(const TriangleSoup& soup, const Mesh& mesh, const SparseMatrix& L) {
  const std::vector<bool> boundary = test::boundary_vertices(soup);
  const Eigen::Index n = L.rows();
  Eigen::VectorXd f(n), x(n), y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Vec3& p = soup.positions[static_cast<std::size_t>(i)];
    x[i] = p.x();
    y[i] = p.y();
    f[i] = 2.0 * p.x() - 3.0 * p.y() + 0.5;
  }
  // Tolerance relative to the row's weights times the coordinate scale.
  const Eigen::VectorXd row_scale = L.cwiseAbs() * Eigen::VectorXd::Ones(n);
  int interior = 0;
  for (const Eigen::VectorXd& g : {f, x, y}) {
    const Eigen::VectorXd lg = L * g;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (boundary[static_cast<std::size_t>(i)] || mesh.is_isolated(Vertex(static_cast<int>(i)))) continue;
      ++interior;
      EXPECT_LE(std::abs(lg[i]), 1e-13 * row_scale[i] * 5.0) << "vertex " << i;
    }
  }
  EXPECT_GT(interior, 0);
}

TEST(CotanLaplacian, LinearPrecisionOnIrregularPlanarMeshes) {
  for (const Case& c : {Case{"plane", make_plane(6, 5, 1.0, 2.0)}, Case{"jittered_plane", jittered_plane()},
                        Case{"jittered_disk", jittered_disk()}, Case{"annulus", make_annulus(0.2, 1.0, 6, 20)}}) {
    SCOPED_TRACE(c.name);
    if (c.name.starts_with("jittered")) {
      EXPECT_GT(count_obtuse(c.soup), 0);  // the test must cover obtuse corners
    }
    const Mesh mesh = Mesh::from_soup(c.soup);
    expect_linear_precision(c.soup, mesh, cotan_laplacian(mesh));
  }
}

TEST(CotanLaplacian, PositionsOverrideUsesGivenEmbedding) {
  // A bumpy surface with a flattened (jittered) parametrization in z = 0.
  TriangleSoup flat = make_plane(10, 8);
  test::jitter_interior(flat, 0.03, 17);
  TriangleSoup bumpy = flat;
  for (Vec3& p : bumpy.positions) p.z() = 0.3 * std::sin(5 * p.x()) * std::cos(4 * p.y());
  const Mesh mesh = Mesh::from_soup(bumpy);
  const VertexData<Vec3> param(flat.positions);
  const SparseMatrix Lp = cotan_laplacian(mesh, param);
  expect_linear_precision(flat, mesh, Lp);
  // The 3D operator has no linear precision in (x, y) here: the override really is used.
  const SparseMatrix L3 = cotan_laplacian(mesh);
  EXPECT_GT(SparseMatrix(L3 - Lp).norm(), 1e-3 * Lp.norm());
  // Same result as building the mesh from the flat soup.
  EXPECT_LT(SparseMatrix(cotan_laplacian(Mesh::from_soup(flat)) - Lp).norm(), 1e-14 * Lp.norm());
}

TEST(CotanLaplacian, PositionsOverrideValidated) {
  const Mesh mesh = Mesh::from_soup(make_plane(2, 2));
  EXPECT_THROW(cotan_laplacian(mesh, VertexData<Vec3>(5, Vec3::Zero())), InvalidInput);
  VertexData<Vec3> bad = mesh.positions();
  bad[Vertex(4)].x() = std::nan("");
  EXPECT_THROW(cotan_laplacian(mesh, bad), InvalidInput);
  EXPECT_THROW(mixed_voronoi_areas(mesh, bad), InvalidInput);
  EXPECT_THROW(cotan_weights(mesh, VertexData<Vec3>(3, Vec3::Zero())), InvalidInput);
}

TriangleSoup soup(std::vector<Vec3> p, std::vector<Tri> f) { return TriangleSoup{std::move(p), std::move(f)}; }

TEST(CotanLaplacian, RightIsoscelesTriangleByHand) {
  // Right angle at vertex 0 (cot 90 = 0), 45 degrees at 1 and 2 (cot 45 = 1).
  const Mesh mesh = Mesh::from_soup(soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}));
  const Eigen::MatrixXd L(cotan_laplacian(mesh));
  Eigen::Matrix3d expected;
  expected << -2, 1, 1,  //
      1, -1, 0,          //
      1, 0, -1;
  EXPECT_LT((L - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(CotanLaplacian, EquilateralRhombusByHand) {
  // Two equilateral triangles sharing edge 1-2: cot 60 = 1/sqrt(3) per face.
  const double h = std::sqrt(3.0) / 2.0;
  const Mesh mesh = Mesh::from_soup(soup({{0, 0, 0}, {1, 0, 0}, {0.5, h, 0}, {1.5, h, 0}}, {{0, 1, 2}, {1, 3, 2}}));
  const Eigen::MatrixXd L(cotan_laplacian(mesh));
  const double c = 1.0 / std::sqrt(3.0);
  EXPECT_NEAR(L(1, 2), 2 * c, 1e-15);
  EXPECT_NEAR(L(0, 1), c, 1e-15);
  EXPECT_NEAR(L(0, 2), c, 1e-15);
  EXPECT_NEAR(L(1, 3), c, 1e-15);
  EXPECT_NEAR(L(2, 3), c, 1e-15);
  EXPECT_EQ(L(0, 3), 0.0);
  EXPECT_NEAR(L(0, 0), -2 * c, 1e-15);
  EXPECT_NEAR(L(1, 1), -4 * c, 1e-15);
  const EdgeData<double> w = cotan_weights(mesh);
  EXPECT_NEAR(w[mesh.edge(mesh.find_halfedge(Vertex(2), Vertex(1)))], 2 * c, 1e-15);
  EXPECT_NEAR(w[mesh.edge(mesh.find_halfedge(Vertex(3), Vertex(1)))], c, 1e-15);
}

TEST(CotanLaplacian, ObtuseTriangleKeepsNegativeWeight) {
  // Apex angle at vertex 2: cot = ((-1,-0.2).(1,-0.2)) / 0.4 = -2.4; base angles: cot = 2 / 0.4 = 5.
  const Mesh mesh = Mesh::from_soup(soup({{0, 0, 0}, {2, 0, 0}, {1, 0.2, 0}}, {{0, 1, 2}}));
  OperatorDiagnostics diag;
  const Eigen::MatrixXd L(cotan_laplacian(mesh, &diag));
  EXPECT_NEAR(L(0, 1), -2.4, 1e-14);
  EXPECT_NEAR(L(0, 2), 5.0, 1e-14);
  EXPECT_NEAR(L(1, 2), 5.0, 1e-14);
  EXPECT_NEAR(L(2, 2), -10.0, 1e-14);
  EXPECT_EQ(diag.clamped_cotangents, 0);
}

TEST(CotanLaplacian, ScaleInvariantAndRotationInvariant) {
  // Cotangents are angles only: scaling and rotating the mesh leaves L unchanged.
  TriangleSoup s = make_icosphere(2);
  const SparseMatrix L0 = cotan_laplacian(Mesh::from_soup(s));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (Vec3& p : s.positions) p = 3.5 * (R * p) + Vec3(1, -2, 4);
  const SparseMatrix L1 = cotan_laplacian(Mesh::from_soup(s));
  EXPECT_LT(SparseMatrix(L1 - L0).norm(), 1e-12 * L0.norm());
}

}  // namespace
}  // namespace freeform
