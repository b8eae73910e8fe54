// Settings, the lambda blend, local assembly against the global operators, the sparse solver
// wrapper and the errors a user can cause (docs/operators.md, docs/bcm.md).
#include "bcm_fixtures.h"

#include "freeform/common/error.h"
#include "freeform/numerics/sparse_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace freeform::test {
namespace {

// The number after the first "vertex " in msg, or -1 (no <regex>: GCC 12 warns inside it).
int named_vertex(const std::string& msg) {
  const auto pos = msg.find("vertex ");
  if (pos == std::string::npos) return -1;
  std::size_t i = pos + 7;
  int value = -1;
  while (i < msg.size() && msg[i] >= '0' && msg[i] <= '9') value = (value < 0 ? 0 : 10 * value) + (msg[i++] - '0');
  return value;
}

// 6. lambda_m(c) = clamp(c - m + 1, 0, 1): values by hand and continuity (the paper's c - k
// would jump).
TEST(Lambda, ValuesByHand) {
  const double cs[] = {0.0, 0.5, 1.0, 1.5, 2.0};
  const double m1[] = {0.0, 0.5, 1.0, 1.0, 1.0};
  const double m2[] = {0.0, 0.0, 0.0, 0.5, 1.0};
  for (int i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(smoothness_lambda(cs[i], 1), m1[i]) << "c=" << cs[i];
    EXPECT_DOUBLE_EQ(smoothness_lambda(cs[i], 2), m2[i]) << "c=" << cs[i];
  }
  EXPECT_DOUBLE_EQ(smoothness_lambda(0.25, 1), 0.25);
  EXPECT_DOUBLE_EQ(smoothness_lambda(1.75, 2), 0.75);
}

TEST(Lambda, ContinuousAndMonotone) {
  for (int m = 1; m <= 2; ++m) {
    double prev = smoothness_lambda(0.0, m);
    for (int i = 1; i <= 2000; ++i) {
      const double c = 2.0 * i / 2000.0;
      const double v = smoothness_lambda(c, m);
      EXPECT_LE(std::abs(v - prev), 1e-3 + 1e-12) << "jump at c=" << c << " m=" << m;
      EXPECT_GE(v, prev);
      prev = v;
    }
  }
}

// 7. Bad settings.
TEST(Settings, Validation) {
  BcmSettings s;
  EXPECT_NO_THROW(validate_settings(s));
  for (int k : {0, 4, -1}) {
    s.order = k;
    EXPECT_THROW(validate_settings(s), InvalidInput) << k;
  }
  s.order = 2;
  for (double bad : {-0.5, 1.5, std::nan(""), std::numeric_limits<double>::infinity()}) {
    BcmSettings a = s;
    a.smoothness.outer = bad;
    EXPECT_THROW(validate_settings(a), InvalidInput) << bad;
    BcmSettings b = s;
    b.smoothness.inner = bad;
    EXPECT_THROW(validate_settings(b), InvalidInput) << bad;
    BcmSettings c = s;
    c.smoothness.segments = {{{Vertex(0)}, bad}};
    EXPECT_THROW(validate_settings(c), InvalidInput) << bad;
  }
  s.order = 1;
  s.smoothness.outer = 0.5;  // > k - 1 = 0
  EXPECT_THROW(validate_settings(s), InvalidInput);
  s.order = 3;
  s.smoothness.outer = 2.0;
  s.smoothness.inner = 0.0;
  s.smoothness.segments = {{{Vertex(0)}, -1.0}};  // the sentinel is only for outer/inner
  EXPECT_THROW(validate_settings(s), InvalidInput);
  s.smoothness.segments = {{{Vertex(0)}, 1.25}};
  EXPECT_NO_THROW(validate_settings(s));
  try {
    BcmSettings a;
    a.smoothness.outer = -0.5;
    validate_settings(a);
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("-0.5"), std::string::npos) << e.what();
  }
}

TEST(Settings, BadSettingsReachTheSolver) {
  const BumpyScene scene;
  BcmSettings s;
  s.order = 4;
  EXPECT_THROW(BcmSolver(scene.mesh, scene.regions(), s), InvalidInput);
  s.order = 2;
  s.smoothness.inner = std::nan("");
  EXPECT_THROW(BcmSolver(scene.mesh, scene.regions(), s), InvalidInput);
  s.smoothness.inner = 1.0;
  s.smoothness.segments = {{{Vertex(1 << 20)}, 0.5}};
  EXPECT_THROW(BcmSolver(scene.mesh, scene.regions(), s), InvalidInput);
}

TEST(Assembly, WholeClosedComponentIsRefusedNamingAVertex) {
  const Mesh sphere = Mesh::from_soup(make_icosphere(2));
  std::vector<Vertex> all;
  for (Vertex v : sphere.vertices()) all.push_back(v);
  const Regions regions(sphere, all, {});
  for (int k = 1; k <= 3; ++k) {
    BcmSettings s;
    s.order = k;
    try {
      const BcmSolver solver(sphere, regions, s);
      ADD_FAILURE() << "expected InvalidInput";
    } catch (const InvalidInput& e) {
      const std::string msg = e.what();
      EXPECT_GE(named_vertex(msg), 0) << msg;
      EXPECT_NE(msg.find("whole component"), std::string::npos) << msg;
      EXPECT_NE(msg.find("add a handle"), std::string::npos) << msg;
    }
  }
  // With a handle the same support is fine.
  const Regions with_handle(sphere, all, {{{Vertex(0), Vertex(1)}, true}});
  EXPECT_NO_THROW(BcmSolver(sphere, with_handle, BcmSettings{}));
}

// A vertex of 4,200 neighbours next to the support would make order-2 rows of millions of
// entries: refused, naming it and the first free vertex in the system's order, also when the
// free vertices are enough for the check to run on several threads (it looks at all of them).
TEST(Assembly, HugeFanIsRefusedNamingTheFirstFreeVertexNextToIt) {
  constexpr int kFans = 5, kRim = 4200;
  TriangleSoup soup;
  for (int f = 0; f < kFans; ++f) {
    const int center = static_cast<int>(soup.positions.size());
    soup.positions.emplace_back(10.0 * f, 0.0, 0.0);
    for (int i = 0; i < kRim; ++i) {
      const double a = 2.0 * std::numbers::pi * i / kRim;
      soup.positions.emplace_back(10.0 * f + std::cos(a), std::sin(a), 0.0);
    }
    for (int i = 0; i < kRim; ++i) soup.faces.push_back({center, center + 1 + i, center + 1 + (i + 1) % kRim});
  }
  const Mesh mesh = Mesh::from_soup(soup);
  // Free: the rim vertices but the first of each fan (fixed, with the centres). Every block of
  // the check meets a huge fan; the refusal names the first in the system's order (breadth-first
  // from the lowest index): vertex 2, next to centre 0.
  std::vector<Vertex> support;
  for (int v = mesh.n_vertices() - 1; v >= 0; --v)
    if (v % (kRim + 1) > 1) support.emplace_back(v);
  const Regions regions(mesh, support, {});
  BcmSettings s;
  s.order = 2;
  try {
    (void)assemble_bcm_system(mesh, mesh.positions(), regions, s);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("vertex 0, near free vertex 2, has 4200 neighbours:"), std::string::npos) << msg;
  }
  s.order = 1;  // a Laplacian row is as wide as the valence: no refusal
  EXPECT_NO_THROW((void)assemble_bcm_system(mesh, mesh.positions(), regions, s));
}

TEST(Assembly, FreeIslandWithoutConstraintIsRefused) {
  // Two separate patches: the second one is a whole closed sphere inside the support.
  TriangleSoup a = make_bumpy_plane(10, 10, 0.05, 1.0);
  const TriangleSoup b = make_icosphere(1, 0.2);
  const int offset = static_cast<int>(a.positions.size());
  for (const Vec3& p : b.positions) a.positions.push_back(p + Vec3(3, 0, 0));
  for (const Tri& t : b.faces) a.faces.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const Mesh mesh = Mesh::from_soup(a);
  std::vector<Vertex> support = within(mesh, Vec3(0.5, 0.5, 0), 0.3);
  for (int i = offset; i < mesh.n_vertices(); ++i) support.push_back(Vertex(i));
  const Regions regions(mesh, support, {{within(mesh, Vec3(0.5, 0.5, 0), 0.05), true}});
  try {
    const BcmSolver solver(mesh, regions, BcmSettings{});
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    const std::string msg = e.what();
    EXPECT_GE(named_vertex(msg), offset) << msg;  // a vertex of the island, not of the patch
  }
}

TEST(Assembly, NonFinitePositionsAreRefused) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  VertexData<Vec3> pos = scene.mesh.positions();
  pos[regions.free_vertices()[3]] = Vec3(std::nan(""), 0, 0);
  EXPECT_THROW(assemble_bcm_system(scene.mesh, pos, regions, BcmSettings{}), InvalidInput);
}

// Local assembly on the k-ring == rows/columns of the global S_k built from operators.h.
TEST(Assembly, LocalMatchesGlobalOperator) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  for (int k = 1; k <= 3; ++k) {
    for (double c : {0.0, 0.3 * (k - 1), k - 1.0}) {
      SCOPED_TRACE("k=" + std::to_string(k) + " c=" + std::to_string(c));
      BcmSettings s;
      s.order = k;
      s.smoothness.outer = c;
      s.smoothness.inner = 0.5 * c;
      const BcmSystem sys = assemble_bcm_system(scene.mesh, scene.mesh.positions(), regions, s);
      const Eigen::MatrixXd g = Eigen::MatrixXd(global_s(scene.mesh, regions, s)) * (k % 2 ? -1.0 : 1.0);
      const auto np = static_cast<Eigen::Index>(sys.free.size());
      const auto nc = static_cast<Eigen::Index>(sys.constrained.size());
      Eigen::MatrixXd want_pp(np, np), want_pc(np, nc);
      for (Eigen::Index i = 0; i < np; ++i) {
        for (Eigen::Index j = 0; j < np; ++j) want_pp(i, j) = g(sys.free[static_cast<std::size_t>(i)].idx(), sys.free[static_cast<std::size_t>(j)].idx());
        for (Eigen::Index j = 0; j < nc; ++j)
          want_pc(i, j) = g(sys.free[static_cast<std::size_t>(i)].idx(), sys.constrained[static_cast<std::size_t>(j)].idx());
      }
      const double scale = want_pp.cwiseAbs().maxCoeff();
      EXPECT_LT((Eigen::MatrixXd(sys.a_pp) - want_pp).cwiseAbs().maxCoeff(), 1e-12 * scale);
      EXPECT_LT((Eigen::MatrixXd(sys.a_pc) - want_pc).cwiseAbs().maxCoeff(), 1e-12 * scale);
      // Every constrained vertex with a nonzero entry anywhere in the global rows is present.
      double outside = 0.0;
      std::vector<char> inside(static_cast<std::size_t>(scene.mesh.n_vertices()), 0);
      for (Vertex v : sys.free) inside[static_cast<std::size_t>(v.idx())] = 1;
      for (Vertex v : sys.constrained) inside[static_cast<std::size_t>(v.idx())] = 1;
      for (Vertex v : sys.free)
        for (int j = 0; j < scene.mesh.n_vertices(); ++j)
          if (!inside[static_cast<std::size_t>(j)]) outside = std::max(outside, std::abs(g(v.idx(), j)));
      EXPECT_EQ(outside, 0.0);
      // The sign makes the diagonal positive; rows of S_k sum to zero.
      EXPECT_GT(Eigen::VectorXd(Eigen::MatrixXd(sys.a_pp).diagonal()).minCoeff(), 0.0);
      const Eigen::VectorXd rows = sys.a_pp * Eigen::VectorXd::Ones(np) + sys.a_pc * Eigen::VectorXd::Ones(nc);
      EXPECT_LT(rows.cwiseAbs().maxCoeff(), 1e-10 * scale);
      EXPECT_EQ(sys.symmetric, is_symmetric(sys.a_pp, 1e-12));
    }
  }
}

TEST(SparseSolver, IsSymmetric) {
  Eigen::SparseMatrix<double> a(3, 3);
  a.insert(0, 0) = 2;
  a.insert(0, 1) = 1;
  a.insert(1, 0) = 1;
  a.insert(2, 2) = 1;
  a.makeCompressed();
  EXPECT_TRUE(is_symmetric(a));
  a.coeffRef(2, 1) = 1e-6;  // structurally unsymmetric
  EXPECT_FALSE(is_symmetric(a));
  EXPECT_TRUE(is_symmetric(a, 1e-5));
  a.coeffRef(2, 1) = 0;
  a.coeffRef(1, 0) = 1.0 + 1e-9;
  EXPECT_FALSE(is_symmetric(a));
  EXPECT_FALSE(is_symmetric(Eigen::SparseMatrix<double>(2, 3)));
}

Eigen::SparseMatrix<double> dense_to_sparse(const Eigen::MatrixXd& d) { return d.sparseView(); }

// 7. Singular or indefinite matrices -> SolverError, never NaN.
TEST(SparseSolver, SingularOrIndefiniteThrows) {
  Eigen::MatrixXd singular_sym(2, 2), indefinite(2, 2), singular_unsym(2, 2);
  singular_sym << 1, 1, 1, 1;
  indefinite << 1, 2, 2, 1;
  singular_unsym << 1, 2, 3, 6;
  for (SolverKind kind : {SolverKind::Auto, SolverKind::CholmodSupernodal, SolverKind::EigenLDLT}) {
    EXPECT_THROW(SparseSolver(dense_to_sparse(singular_sym), true, kind), SolverError);
    EXPECT_THROW(SparseSolver(dense_to_sparse(indefinite), true, kind), SolverError);
  }
  for (SolverKind kind : {SolverKind::Auto, SolverKind::Umfpack, SolverKind::EigenSparseLU}) {
    EXPECT_THROW(SparseSolver(dense_to_sparse(singular_unsym), false, kind), SolverError);
    EXPECT_THROW(SparseSolver(dense_to_sparse(singular_sym), false, kind), SolverError);
  }
  // Graph Laplacian of a path: positive semi-definite, singular (constants in the kernel).
  const int n = 50;
  Eigen::SparseMatrix<double> path(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i + 1 < n; ++i) {
    t.emplace_back(i, i + 1, -1);
    t.emplace_back(i + 1, i, -1);
    t.emplace_back(i, i, 1);
    t.emplace_back(i + 1, i + 1, 1);
  }
  path.setFromTriplets(t.begin(), t.end());
  for (SolverKind kind : {SolverKind::Auto, SolverKind::CholmodSupernodal, SolverKind::EigenLDLT, SolverKind::Umfpack,
                          SolverKind::EigenSparseLU}) {
    const bool symmetric = kind != SolverKind::Umfpack && kind != SolverKind::EigenSparseLU;
    EXPECT_THROW(SparseSolver(Eigen::SparseMatrix<double>(path), symmetric, kind), SolverError);
  }
  Eigen::MatrixXd nan_matrix = Eigen::MatrixXd::Identity(2, 2);
  nan_matrix(1, 1) = std::nan("");
  EXPECT_THROW(SparseSolver(dense_to_sparse(nan_matrix), false), SolverError);
  EXPECT_THROW(SparseSolver(Eigen::SparseMatrix<double>(2, 3), false), InvalidInput);
  Eigen::MatrixXd unsym(2, 2);
  unsym << 2, 1, 0, 2;
  EXPECT_THROW(SparseSolver(dense_to_sparse(unsym), true), InvalidInput);
  EXPECT_THROW(SparseSolver(dense_to_sparse(unsym), false, SolverKind::EigenLDLT), InvalidInput);
}

TEST(SparseSolver, SolvesAndReportsItsName) {
  Eigen::MatrixXd spd(3, 3), gen(3, 3);
  spd << 4, 1, 0, 1, 3, 1, 0, 1, 2;
  gen << 4, 1, 0, 2, 3, 1, 0, -1, 2;
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(3, 4);
  const std::vector<std::pair<SolverKind, std::string>> sym = {{SolverKind::Auto, "cholmod-supernodal-llt"},
                                                               {SolverKind::CholmodSupernodal, "cholmod-supernodal-llt"},
                                                               {SolverKind::EigenLDLT, "eigen-simplicial-ldlt"},
                                                               {SolverKind::Umfpack, "umfpack-lu"},
                                                               {SolverKind::EigenSparseLU, "eigen-sparselu"}};
  for (const auto& [kind, name] : sym) {
    const SparseSolver s(dense_to_sparse(spd), kind != SolverKind::Umfpack && kind != SolverKind::EigenSparseLU, kind);
    EXPECT_EQ(s.name(), name);
    const Eigen::MatrixXd x = s.solve(b);
    EXPECT_LT((spd * x - b).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(s.relative_residual(x, b), 1e-12);
  }
  const SparseSolver lu(dense_to_sparse(gen), false);
  EXPECT_EQ(lu.name(), "umfpack-lu");
  EXPECT_LT((gen * lu.solve(b) - b).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(lu.solve(Eigen::MatrixXd::Ones(2, 1)), InvalidInput);
  SparseSolver moved = std::move(const_cast<SparseSolver&>(lu));
  EXPECT_EQ(moved.name(), "umfpack-lu");
}

// The solver takes A's storage (Eigen 3.4's SparseMatrix has no move constructor: std::move into
// a by-value parameter copied 443 MB twice at 1M free); a Cholesky solver keeps only the lower
// triangle, and its residual, through the symmetric view, matches the full matrix's.
TEST(SparseSolver, TakesTheMatrixWithoutACopy) {
  Eigen::MatrixXd spd(3, 3), gen(3, 3);
  spd << 4, 1, 0, 1, 3, 1, 0, 1, 2;
  gen << 4, 1, 0, 2, 3, 1, 0, -1, 2;
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(3, 2);
  for (const auto& [m, symmetric] : {std::pair{spd, true}, std::pair{gen, false}}) {
    Eigen::SparseMatrix<double> a = dense_to_sparse(m);
    const SparseSolver s(std::move(a), symmetric);
    EXPECT_EQ(a.nonZeros(), 0);  // taken, not copied
    const Eigen::MatrixXd x = s.solve(b);
    const Eigen::MatrixXd off = m * (x + Eigen::MatrixXd::Constant(3, 2, 1e-3)) - b;  // a wrong answer
    double want = 0.0;
    for (Eigen::Index j = 0; j < b.cols(); ++j) want = std::max(want, off.col(j).norm() / b.col(j).norm());
    EXPECT_NEAR(s.relative_residual(x + Eigen::MatrixXd::Constant(3, 2, 1e-3), b), want, 1e-12 * want);
  }
}

}  // namespace
}  // namespace freeform::test
