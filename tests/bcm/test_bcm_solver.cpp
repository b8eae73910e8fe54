// BcmSolver invariants (docs/bcm.md): basis == direct solve, partition of unity,
// identity reproduction, linear precision, solver choice, what evaluate() writes.
#include "bcm_fixtures.h"

#include "freeform/common/error.h"
#include "freeform/numerics/sparse_solver.h"

#include <gtest/gtest.h>

#include <string>

namespace freeform::test {
namespace {

struct Case {
  int order;
  double outer, inner;
  bool symmetric;
};

std::string describe(const Case& c) {
  return "k=" + std::to_string(c.order) + " outer=" + std::to_string(c.outer) + " inner=" + std::to_string(c.inner);
}

const std::vector<Case> kCases = {
    {1, -1, -1, true},  {2, -1, -1, true}, {2, 0.5, 0.25, true}, {2, 0, 1, true},
    {3, -1, -1, true},  {3, 0, 2, true},   {3, 0, 0, true},      {3, 1.5, 0.5, false},
    {3, 1, -1, false},  {3, 2, 1.5, false},
};

BcmSettings settings_of(const Case& c) {
  BcmSettings s;
  s.order = c.order;
  s.smoothness.outer = c.outer;
  s.smoothness.inner = c.inner;
  return s;
}

// 1. Basis result == independent direct sparse solve with the moved handles.
TEST(BcmSolver, BasisMatchesDirectSolveWithMovedHandles) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  ASSERT_EQ(regions.n_movable(), 2);
  std::mt19937 rng(42);
  for (const Case& c : kCases) {
    SCOPED_TRACE(describe(c));
    const BcmSettings s = settings_of(c);
    const BcmSolver solver(scene.mesh, regions, s);
    EXPECT_LT(solver.stats().residual, 1e-10);
    for (int trial = 0; trial < 3; ++trial) {
      const std::vector<Eigen::Affine3d> t = {trial == 2 ? random_general_affine(rng) : random_affine(rng),
                                              random_affine(rng)};
      const RowMatrix got = evaluate_by_vertex(solver, t);
      const RowMatrix want = reference_solve(scene.mesh, regions, s, t);
      EXPECT_LT(rel_diff(got, want), 1e-8) << "trial " << trial;
      // The moved result really differs from the base (the test can fail).
      EXPECT_GT(rel_diff(got, evaluate_by_vertex(solver, {Eigen::Affine3d::Identity(), Eigen::Affine3d::Identity()})), 1e-3);
    }
  }
}

// The rest solution (one 3-column solve, no basis) is the direct solve with every handle at
// rest, and what the basis gives there; elsewhere it keeps the mesh's positions.
TEST(BcmSolver, RestSolutionMatchesDirectSolveAndTheBasis) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  const std::vector<Eigen::Affine3d> rest(2, Eigen::Affine3d::Identity());
  for (const Case& c : kCases) {
    SCOPED_TRACE(describe(c));
    const BcmSettings s = settings_of(c);
    const BcmRestSolution fill = bcm_rest_solution(scene.mesh, regions, s);
    const BcmSolver solver(scene.mesh, regions, s);
    ASSERT_EQ(fill.free, solver.free_vertices());
    const RowMatrix want = reference_solve(scene.mesh, regions, s, rest);
    const RowMatrix basis = evaluate_by_vertex(solver, rest);
    RowMatrix got(want.rows(), 3);
    const std::vector<Vertex>& free = regions.free_vertices();
    for (std::size_t i = 0; i < free.size(); ++i)
      got.row(static_cast<Eigen::Index>(i)) = fill.positions[free[i]].transpose();
    EXPECT_LT(rel_diff(got, want), 1e-8);
    EXPECT_LT(rel_diff(got, basis), 1e-10);
    // The support really moved off the bumpy mesh (the comparison can fail), the rest did not.
    RowMatrix mesh_rows(want.rows(), 3);
    for (std::size_t i = 0; i < free.size(); ++i)
      mesh_rows.row(static_cast<Eigen::Index>(i)) = scene.mesh.position(free[i]).transpose();
    EXPECT_GT(rel_diff(got, mesh_rows), 1e-3);
    for (Vertex v : scene.mesh.vertices())
      if (regions.role(v) != Role::Free) {
        EXPECT_EQ(fill.positions[v], scene.mesh.position(v));
      }
  }
  BcmSettings anisotropic;
  anisotropic.anisotropic = true;
  EXPECT_THROW(bcm_rest_solution(scene.mesh, regions, anisotropic), InvalidInput);
}

TEST(BcmSolver, BasisMatchesDirectSolveWithSmoothnessSegmentsAndOpenBoundary) {
  // Support touching the mesh boundary on three sides (free vertices on the open boundary).
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(20, 20, 0.1, 1.0));
  std::vector<Vertex> support, handle;
  for (Vertex v : mesh.vertices()) {
    const Vec3& p = mesh.position(v);
    if (p.y() < 0.52) support.push_back(v);
    if (p.y() > 0.18 && p.y() < 0.27 && p.x() > 0.38 && p.x() < 0.62) handle.push_back(v);
  }
  const Regions regions(mesh, support, {{handle, true}});
  std::mt19937 rng(3);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k=" + std::to_string(k));
    BcmSettings s;
    s.order = k;
    SmoothnessSegment seg{{}, 0.3 * (k - 1)};
    for (Vertex v : mesh.vertices())
      if (regions.role(v) == Role::Fixed && mesh.position(v).x() < 0.5) seg.vertices.push_back(v);
    s.smoothness.segments = {seg};
    const BcmSolver solver(mesh, regions, s);
    const std::vector<Eigen::Affine3d> t = {random_affine(rng)};
    EXPECT_LT(rel_diff(evaluate_by_vertex(solver, t), reference_solve(mesh, regions, s, t)), 1e-8);
  }
}

TEST(BcmSolver, SingleVertexHandleUsesMeanEdgeLengthFrame) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(16, 16, 0.05, 1.0));
  const std::vector<Vertex> handle = within(mesh, Vec3(0.5, 0.5, 0), 0.01);
  ASSERT_EQ(handle.size(), 1u);
  const Regions regions(mesh, within(mesh, Vec3(0.5, 0.5, 0), 0.35), {{handle, true}});
  BcmSettings s;
  s.order = 3;
  const BcmSolver solver(mesh, regions, s);
  double mean = 0.0;
  int n = 0;
  for (Halfedge h : mesh.outgoing(handle[0])) {
    mean += (mesh.position(mesh.to_vertex(h)) - mesh.position(handle[0])).norm();
    ++n;
  }
  mean /= n;
  const auto& f = solver.frame(0);
  EXPECT_LT((f[0] - mesh.position(handle[0])).norm(), 1e-15);
  for (int i = 1; i < 4; ++i) EXPECT_NEAR((f[static_cast<std::size_t>(i)] - f[0]).norm(), mean, 1e-14);
  std::mt19937 rng(5);
  const std::vector<Eigen::Affine3d> t = {random_affine(rng)};
  EXPECT_LT(rel_diff(evaluate_by_vertex(solver, t), reference_solve(mesh, regions, s, t)), 1e-8);
}

// 2. Partition of unity, and translating everything translates every free vertex.
TEST(BcmSolver, PartitionOfUnity) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  for (const Case& c : kCases) {
    SCOPED_TRACE(describe(c));
    const BcmSettings s = settings_of(c);
    const BcmSolver solver(scene.mesh, regions, s);
    const BcmSystem sys = assemble_bcm_system(scene.mesh, scene.mesh.positions(), regions, s);
    // Constant part with f = 1 (fixed and immovable-handle columns), solved independently.
    Eigen::VectorXd f1 = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(sys.constrained.size()));
    for (std::size_t j = 0; j < sys.constrained.size(); ++j) {
      const int h = regions.handle_of(sys.constrained[j]);
      if (h < 0 || regions.movable_index(h) < 0) f1[static_cast<Eigen::Index>(j)] = 1.0;
    }
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(sys.a_pp);
    ASSERT_EQ(lu.info(), Eigen::Success);
    const Eigen::VectorXd const1 = lu.solve(Eigen::VectorXd(-(sys.a_pc * f1)));
    const Eigen::VectorXd sum = const1 + solver.basis() * Eigen::VectorXd::Ones(solver.basis().cols());
    EXPECT_LT((sum - Eigen::VectorXd::Ones(sum.size())).cwiseAbs().maxCoeff(), 1e-9);
    // Each handle's four basis columns carry real weight (not a vacuous sum).
    EXPECT_GT(solver.basis().cwiseAbs().maxCoeff(), 1e-3);
  }
}

TEST(BcmSolver, TranslatingEverythingTranslatesFreeVertices) {
  const BumpyScene scene;
  const Vec3 shift(0.3, -1.7, 2.5);
  Mesh moved = scene.mesh;
  for (Vertex v : moved.vertices()) moved.position(v) += shift;
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k=" + std::to_string(k));
    BcmSettings s;
    s.order = k;
    s.smoothness.outer = 0.5 * (k - 1);
    const BcmSolver a(scene.mesh, scene.regions(), s);
    const BcmSolver b(moved, Regions(moved, scene.support, scene.handles), s);
    const std::vector<Eigen::Affine3d> id(2, Eigen::Affine3d::Identity());
    const RowMatrix pa = evaluate(a, id);
    const RowMatrix pb = evaluate(b, id);
    EXPECT_LT((pb.rowwise() - shift.transpose() - pa).cwiseAbs().maxCoeff(), 1e-10);
  }
}

// 3. Identity manipulator: the base solution; on a planar support the input itself.
TEST(BcmSolver, IdentityReproducesBase) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  for (const Case& c : kCases) {
    SCOPED_TRACE(describe(c));
    const BcmSettings s = settings_of(c);
    const BcmSolver solver(scene.mesh, regions, s);
    const std::vector<Eigen::Affine3d> id(2, Eigen::Affine3d::Identity());
    const RowMatrix base = evaluate(solver, id);
    EXPECT_LT(rel_diff(evaluate_by_vertex(solver, id), reference_solve(scene.mesh, regions, s, id)), 1e-8);
    // The base is P_const + sum_m B_m F0_m.
    RowMatrix manual = solver.constant_part();
    for (int m = 0; m < 2; ++m)
      for (int j = 0; j < 4; ++j)
        manual += solver.basis().col(4 * m + j) * solver.frame(m)[static_cast<std::size_t>(j)].transpose();
    EXPECT_LT(rel_diff(base, manual), 1e-12);
  }
}

TEST(BcmSolver, IdentityOnPlanarSupportReproducesInput) {
  const PlanarDisk disk;
  const Regions regions(disk.mesh, disk.rings(0, 6), {{disk.rings(0, 1), true}});
  for (int k = 1; k <= 3; ++k) {
    for (double c : {0.0, 0.5 * (k - 1), k - 1.0}) {
      SCOPED_TRACE("k=" + std::to_string(k) + " c=" + std::to_string(c));
      BcmSettings s;
      s.order = k;
      s.smoothness.outer = c;
      s.smoothness.inner = c;
      const BcmSolver solver(disk.mesh, regions, s);
      VertexData<Vec3> pos(static_cast<std::size_t>(disk.mesh.n_vertices()), Vec3::Zero());
      solver.evaluate(std::vector<Eigen::Affine3d>{Eigen::Affine3d::Identity()}, pos);
      for (Vertex v : regions.free_vertices()) EXPECT_LT((pos[v] - disk.mesh.position(v)).norm(), 1e-11);
    }
  }
}

// 4. Linear precision: one affine map on every constrained vertex moves every free vertex by it.
TEST(BcmSolver, LinearPrecisionOnPlanarRegion) {
  const PlanarDisk disk;
  std::mt19937 rng(11);
  // No fixed vertex: an outer movable handle (rings 7-10) and an inner one (rings 0-1).
  const Regions regions(disk.mesh, disk.rings(0, 10), {{disk.rings(0, 1), true}, {disk.rings(7, 10), true}});
  ASSERT_EQ(regions.n_fixed(), 0);
  for (int k = 1; k <= 3; ++k) {
    for (double c : {0.5 * (k - 1), k - 1.0}) {
      SCOPED_TRACE("k=" + std::to_string(k) + " c=" + std::to_string(c));
      BcmSettings s;
      s.order = k;
      s.smoothness.inner = c;
      const BcmSolver solver(disk.mesh, regions, s);
      const Eigen::Affine3d t = random_general_affine(rng);
      const RowMatrix got = evaluate(solver, {t, t});
      double err = 0.0;
      for (std::size_t i = 0; i < solver.free_vertices().size(); ++i)
        err = std::max(err, (got.row(static_cast<Eigen::Index>(i)).transpose() - t * disk.mesh.position(solver.free_vertices()[i])).norm());
      EXPECT_LT(err, 1e-10);
    }
  }
}

TEST(BcmSolver, LinearPrecisionWithFixedVerticesAtSystemLevel) {
  const PlanarDisk disk;
  std::mt19937 rng(13);
  const Regions regions(disk.mesh, disk.rings(0, 6), {{disk.rings(0, 1), true}});
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k=" + std::to_string(k));
    BcmSettings s;
    s.order = k;
    s.smoothness.outer = 0.4 * (k - 1);
    const BcmSystem sys = assemble_bcm_system(disk.mesh, disk.mesh.positions(), regions, s);
    const Eigen::Affine3d t = random_general_affine(rng);
    Eigen::MatrixXd xc(static_cast<Eigen::Index>(sys.constrained.size()), 3);
    for (std::size_t j = 0; j < sys.constrained.size(); ++j)
      xc.row(static_cast<Eigen::Index>(j)) = (t * disk.mesh.position(sys.constrained[j])).transpose();
    const SparseSolver solver(Eigen::SparseMatrix<double>(sys.a_pp), sys.symmetric);
    const Eigen::MatrixXd p = solver.solve(-(sys.a_pc * xc));
    double err = 0.0;
    for (std::size_t i = 0; i < sys.free.size(); ++i)
      err = std::max(err, (p.row(static_cast<Eigen::Index>(i)).transpose() - t * disk.mesh.position(sys.free[i])).norm());
    EXPECT_LT(err, 1e-10);
  }
}

// 5. Symmetry decides the solver; forcing any applicable solver gives the same result.
TEST(BcmSolver, SymmetryAndSolverChoice) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  for (const Case& c : kCases) {
    SCOPED_TRACE(describe(c));
    const BcmSolver solver(scene.mesh, regions, settings_of(c));
    EXPECT_EQ(solver.stats().symmetric, c.symmetric);
    EXPECT_NE(solver.stats().solver.find(c.symmetric ? "cholmod" : "umfpack"), std::string::npos)
        << solver.stats().solver;
  }
}

TEST(BcmSolver, ForcedSolversAgree) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  std::mt19937 rng(17);
  const std::vector<Eigen::Affine3d> t = {random_affine(rng), random_affine(rng)};
  for (const Case& c : {Case{2, 0.5, 1, true}, Case{3, 0, 2, true}, Case{3, 1.5, 0.5, false}}) {
    SCOPED_TRACE(describe(c));
    BcmSettings s = settings_of(c);
    const RowMatrix want = evaluate(BcmSolver(scene.mesh, regions, s), t);
    const std::vector<std::pair<SolverKind, std::string>> kinds = {{SolverKind::CholmodSupernodal, "cholmod"},
                                                                   {SolverKind::EigenLDLT, "ldlt"},
                                                                   {SolverKind::Umfpack, "umfpack"},
                                                                   {SolverKind::EigenSparseLU, "sparselu"}};
    for (const auto& [kind, name] : kinds) {
      s.solver = kind;
      const bool cholesky = kind == SolverKind::CholmodSupernodal || kind == SolverKind::EigenLDLT;
      if (cholesky && !c.symmetric) {
        EXPECT_THROW(BcmSolver(scene.mesh, regions, s), InvalidInput);
        continue;
      }
      const BcmSolver solver(scene.mesh, regions, s);
      EXPECT_NE(solver.stats().solver.find(name), std::string::npos) << solver.stats().solver;
      EXPECT_LT(rel_diff(evaluate(solver, t), want), 1e-9) << name;
    }
  }
}

// 8. evaluate() writes exactly the free and movable-handle vertices; handles move rigidly.
TEST(BcmSolver, EvaluateWritesOnlyFreeAndMovableHandleVertices) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  BcmSettings s;
  s.order = 3;
  const BcmSolver solver(scene.mesh, regions, s);
  std::mt19937 rng(19);
  const std::vector<Eigen::Affine3d> t = {random_affine(rng), random_general_affine(rng)};
  const Vec3 sentinel(1e9, -1e9, 7.0);
  VertexData<Vec3> pos(static_cast<std::size_t>(scene.mesh.n_vertices()), sentinel);
  solver.evaluate(t, pos);
  const RowMatrix free = evaluate(solver, t);
  int n_free = 0, n_handle = 0, n_untouched = 0;
  for (Vertex v : scene.mesh.vertices()) {
    const int h = regions.handle_of(v);
    if (regions.role(v) == Role::Free) {
      const auto it = std::find(solver.free_vertices().begin(), solver.free_vertices().end(), v);
      EXPECT_EQ((pos[v].transpose() - free.row(it - solver.free_vertices().begin())).norm(), 0.0);
      ++n_free;
    } else if (h >= 0 && regions.movable_index(h) >= 0) {
      EXPECT_LT((pos[v] - t[static_cast<std::size_t>(regions.movable_index(h))] * scene.mesh.position(v)).norm(), 1e-14);
      ++n_handle;
    } else {
      EXPECT_EQ(pos[v], sentinel) << "vertex " << v.idx() << " must not be written";
      ++n_untouched;
    }
  }
  EXPECT_EQ(n_free, regions.n_free());
  EXPECT_EQ(n_handle, 14);
  EXPECT_EQ(n_untouched, scene.mesh.n_vertices() - regions.n_free() - 14);
}

TEST(BcmSolver, EvaluateIntoStridedBlockAndParallelPathMatchSerialProduct) {
  // Enough free vertices (> 4096) for the parallel path.
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(90, 90, 0.05, 1.0));
  const Regions regions(mesh, within(mesh, Vec3(0.5, 0.5, 0), 0.45), {{within(mesh, Vec3(0.5, 0.5, 0), 0.03), true}});
  ASSERT_GT(regions.n_free(), 5000);
  BcmSettings s;
  s.order = 1;
  const BcmSolver solver(mesh, regions, s);
  std::mt19937 rng(23);
  const std::vector<Eigen::Affine3d> t = {random_affine(rng)};
  Eigen::Matrix<double, Eigen::Dynamic, 3> g(4, 3);
  for (int j = 0; j < 4; ++j) g.row(j) = (t[0] * solver.frame(0)[static_cast<std::size_t>(j)]).transpose();
  const Eigen::MatrixXd want = Eigen::MatrixXd(solver.constant_part()) + Eigen::MatrixXd(solver.basis()) * g;
  Eigen::Matrix<double, Eigen::Dynamic, 5, Eigen::RowMajor> wide(solver.n_free(), 5);
  wide.setConstant(-3.0);
  solver.evaluate(t, wide.leftCols<3>());
  EXPECT_LT(rel_diff(wide.leftCols<3>(), want), 1e-14);
  EXPECT_TRUE((wide.rightCols<2>().array() == -3.0).all());
}

TEST(BcmSolver, OnlyImmovableHandlesAndManyMovableHandles) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(30, 30, 0.06, 1.0));
  const std::vector<Vertex> support = within(mesh, Vec3(0.5, 0.5, 0), 0.45);
  BcmSettings s;
  s.order = 2;
  {  // M = 0: everything is in the constant part.
    const Regions regions(mesh, support, {{within(mesh, Vec3(0.5, 0.5, 0), 0.05), false}});
    const BcmSolver solver(mesh, regions, s);
    EXPECT_EQ(solver.n_movable(), 0);
    EXPECT_LT(rel_diff(evaluate_by_vertex(solver, {}), reference_solve(mesh, regions, s, {})), 1e-8);
  }
  {  // M = 36 > kStackHandles: the preallocated frame buffer.
    std::vector<HandleRegion> handles;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) handles.push_back({within(mesh, Vec3(0.2 + 0.1 * i, 0.2 + 0.1 * j, 0), 0.01), true});
    const Regions regions(mesh, support, handles);
    ASSERT_GT(regions.n_movable(), BcmSolver::kStackHandles);
    const BcmSolver solver(mesh, regions, s);
    std::mt19937 rng(29);
    std::vector<Eigen::Affine3d> t;
    for (int m = 0; m < regions.n_movable(); ++m) t.push_back(random_affine(rng));
    EXPECT_LT(rel_diff(evaluate_by_vertex(solver, t), reference_solve(mesh, regions, s, t)), 1e-8);
  }
}

// RowOrder::ByIndex: the same solution with rows sorted by vertex; the scatter into the mesh
// writes the same positions. A kept system (breadth-first rows) refuses it.
TEST(BcmSolver, RowsByIndexAreTheBreadthFirstRowsSorted) {
  const BumpyScene scene;
  const Regions regions = scene.regions();
  const BcmSolver bfs(scene.mesh, regions, BcmSettings{});
  const BcmSolver by_index(scene.mesh, regions, BcmSettings{}, {}, nullptr, false, RowOrder::ByIndex);
  EXPECT_TRUE(std::is_sorted(by_index.free_vertices().begin(), by_index.free_vertices().end()));
  EXPECT_FALSE(std::is_sorted(bfs.free_vertices().begin(), bfs.free_vertices().end()));  // the test means something
  std::mt19937 rng(41);
  const std::vector<Eigen::Affine3d> t = {random_affine(rng), random_affine(rng)};
  EXPECT_EQ(evaluate(by_index, t), evaluate_by_vertex(bfs, t));
  VertexData<Vec3> a = scene.mesh.positions(), b = scene.mesh.positions();
  bfs.evaluate(t, a);
  by_index.evaluate(t, b);
  EXPECT_TRUE(a.raw() == b.raw());
  EXPECT_THROW(BcmSolver(scene.mesh, regions, BcmSettings{}, {}, nullptr, true, RowOrder::ByIndex), InvalidInput);
}

TEST(BcmSolver, EvaluateRejectsWrongArguments) {
  const BumpyScene scene;
  const BcmSolver solver(scene.mesh, scene.regions(), BcmSettings{});
  RowMatrix out(solver.n_free(), 3);
  EXPECT_THROW(solver.evaluate(std::vector<Eigen::Affine3d>(1, Eigen::Affine3d::Identity()), out), InvalidInput);
  Eigen::Affine3d nan = Eigen::Affine3d::Identity();
  nan(0, 3) = std::nan("");
  EXPECT_THROW(solver.evaluate(std::vector<Eigen::Affine3d>{nan, nan}, out), InvalidInput);
  RowMatrix small(3, 3);
  EXPECT_THROW(solver.evaluate(std::vector<Eigen::Affine3d>(2, Eigen::Affine3d::Identity()), small), InvalidInput);
  VertexData<Vec3> pos(3, Vec3::Zero());
  EXPECT_THROW(solver.evaluate(std::vector<Eigen::Affine3d>(2, Eigen::Affine3d::Identity()), pos), InvalidInput);
  EXPECT_THROW(solver.handle_centroid(2), InvalidInput);
  EXPECT_EQ(solver.n_movable(), 2);
}

}  // namespace
}  // namespace freeform::test
