// The one-shot deform() and EditSolver (edit/edit_solver.h): sanity on a flat grid for k = 1..3.
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <string>
#include <vector>

using namespace freeform;
using ::testing::HasSubstr;

namespace {

// 21 x 21 grid on the unit square; support: disk of radius 0.31 around the centre; handle: disk
// of radius 0.11 around the centre (13 vertices). The support stays 4 rings away from the
// mesh boundary, so the k-ring stencils never see it (linear precision holds).
struct Fixture {
  Mesh mesh = Mesh::from_soup(make_plane(20, 20));
  Edit edit;
  explicit Fixture(int order, const Vec3& t = Vec3(0, 0, 0.2)) {
    edit = parse_edit_text(R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.31}},
                               "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.11}}}]})",
                           mesh, "test", ".");
    edit.settings.order = order;
    edit.handles[0].manipulator.translation = t;
  }
};

bool contains(const std::vector<Vertex>& vs, Vertex v) { return std::binary_search(vs.begin(), vs.end(), v); }

}  // namespace

class DeformOrder : public ::testing::TestWithParam<int> {};

TEST_P(DeformOrder, TranslatingTheOnlyHandle) {
  const Vec3 t(0, 0, 0.2);
  const Fixture f(GetParam(), t);
  EditStats edit_stats;
  const Mesh out = deform(f.mesh, f.edit, &edit_stats);
  const BcmStats& stats = edit_stats.bcm;
  ASSERT_EQ(out.n_vertices(), f.mesh.n_vertices());
  ASSERT_EQ(out.n_faces(), f.mesh.n_faces());
  EXPECT_FALSE(stats.solver.empty());
  EXPECT_GT(stats.free, 0);
  EXPECT_TRUE(edit_stats.multires.has_value());  // the default
  const auto& handle = f.edit.handles[0].vertices;
  int free = 0;
  for (Vertex v : f.mesh.vertices()) {
    const Vec3 before = f.mesh.position(v), after = out.position(v);
    if (contains(handle, v)) {
      EXPECT_LT((after - (before + t)).norm(), 1e-12) << "handle vertex " << v.idx();
    } else if (!contains(f.edit.support, v)) {
      EXPECT_EQ(after, before) << "fixed vertex " << v.idx();
    } else {
      ++free;
      ASSERT_TRUE(after.allFinite());
      // Between the fixed plane and the lifted handle (small over/undershoot for k > 1).
      const double slack = GetParam() == 1 ? 1e-9 : 0.1 * t.z();
      EXPECT_GE(after.z(), -slack) << v.idx();
      EXPECT_LE(after.z(), t.z() + slack) << v.idx();
      // A vertical translation of a flat patch moves nothing sideways (symmetry of the setup
      // is not exact on this triangulation, so only approximately).
      EXPECT_LT((after.head<2>() - before.head<2>()).norm(), 0.05) << v.idx();
    }
  }
  EXPECT_EQ(free, stats.free);
}

INSTANTIATE_TEST_SUITE_P(Orders, DeformOrder, ::testing::Values(1, 2, 3));

TEST(Deform, IdentityLeavesTheMeshUnchanged) {
  const Fixture f(3, Vec3::Zero());
  const Mesh out = deform(f.mesh, f.edit);
  for (Vertex v : f.mesh.vertices()) EXPECT_LT((out.position(v) - f.mesh.position(v)).norm(), 1e-9);
}

TEST(Deform, DefaultPivotIsTheHandleCentroid) {
  Fixture f(2, Vec3::Zero());
  f.edit.handles[0].manipulator.rotation = Manipulator::axis_angle(Vec3(0, 0, 1), 90);
  f.edit.handles[0].manipulator.scale = Vec3(2, 2, 2);
  const EditSolver solver(f.mesh, f.edit);
  const auto transforms = solver.transforms(f.edit);
  ASSERT_EQ(transforms.size(), 1u);
  const Vec3 c = solver.handle_centroid(0);
  EXPECT_LT((transforms[0] * c - c).norm(), 1e-12);
  EXPECT_LT((transforms[0].linear() * Vec3(1, 0, 0) - Vec3(0, 2, 0)).norm(), 1e-12);
}

TEST(Deform, MatrixAndFixedHandles) {
  Fixture f(2);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m(0, 3) = 0.05;
  f.edit.handles[0].matrix = Eigen::Affine3d(m);
  EditHandle fixed;
  fixed.movable = false;
  fixed.vertices = {Vertex(10 * 21 + 14)};  // (0.7, 0.5): inside the support, held in place
  f.edit.handles.push_back(fixed);
  const Mesh out = deform(f.mesh, f.edit);
  EXPECT_EQ(out.position(fixed.vertices[0]), f.mesh.position(fixed.vertices[0]));
  for (Vertex v : f.edit.handles[0].vertices) EXPECT_LT((out.position(v) - f.mesh.position(v) - Vec3(0.05, 0, 0)).norm(), 1e-12);
}

TEST(Deform, RefusesWhatIsNotAvailableOrNotSolvable) {
  Fixture f(2);
  f.edit.settings.anisotropic = true;  // available (tests/anisotropic): the edit goes through
  EditStats stats;
  EXPECT_NO_THROW((void)deform(f.mesh, f.edit, &stats));
  EXPECT_TRUE(stats.bcm.anisotropic || !stats.bcm.anisotropic_fallback.empty());
  f.edit.settings.anisotropic = false;

  // A closed sphere whose support is every vertex and that has no handle: nothing holds it.
  const Mesh sphere = Mesh::from_soup(make_icosphere(1));
  Edit all;
  for (Vertex v : sphere.vertices()) all.support.push_back(v);
  EXPECT_THROW((void)deform(sphere, all), InvalidInput);
}

// Multiresolution is the default; on a flat patch there is no detail, so it equals plain BCM.
TEST(Deform, MultiresolutionIsTheDefaultAndMatchesPlainBcmWithoutDetail) {
  Fixture f(2);
  EXPECT_TRUE(f.edit.multiresolution);
  const Mesh multires = deform(f.mesh, f.edit);
  f.edit.multiresolution = false;
  const Mesh plain = deform(f.mesh, f.edit);
  for (Vertex v : f.mesh.vertices()) EXPECT_LT((multires.position(v) - plain.position(v)).norm(), 1e-12) << v.idx();
}

// touched() is exactly the set of vertices a frame can move: every vertex that moves under a
// random two-handle edit is in it, and it is the free plus the movable-handle vertices.
TEST(EditSolver, TouchedCoversEveryMovedVertexAndNothingElse) {
  for (const bool multires : {false, true}) {
    Fixture f(3);
    f.edit.multiresolution = multires;
    EditHandle still;
    still.movable = false;
    still.vertices = {Vertex(10 * 21 + 14)};
    f.edit.handles.push_back(still);
    const EditSolver solver(f.mesh, f.edit);
    const std::vector<Vertex>& touched = solver.touched();
    EXPECT_TRUE(std::is_sorted(touched.begin(), touched.end()));
    EXPECT_EQ(static_cast<int>(touched.size()),
              solver.regions().n_free() + static_cast<int>(f.edit.handles[0].vertices.size()));
    EXPECT_FALSE(contains(touched, still.vertices[0]));
    Eigen::Affine3d t = Eigen::Affine3d::Identity();
    t.rotate(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()));
    t.translation() = Vec3(0.1, -0.05, 0.3);
    const std::vector<Eigen::Affine3d> transforms{t};
    VertexData<Vec3> positions = f.mesh.positions();
    solver.evaluate(transforms, positions);
    int moved = 0;
    for (Vertex v : f.mesh.vertices()) {
      if (positions[v] == f.mesh.position(v)) continue;
      ++moved;
      EXPECT_TRUE(contains(touched, v)) << "vertex " << v.idx() << " moved but is not in touched()";
    }
    EXPECT_EQ(moved, static_cast<int>(touched.size()));  // a generic motion moves all of them
    EXPECT_EQ(solver.problems(positions).non_finite, 0);
    EXPECT_GE(solver.last_timings().evaluate_ms, 0.0);
    EXPECT_EQ(solver.last_timings().reconstruction_ms > 0.0 || !multires, true);
  }
}

TEST(EditSolver, EvaluateEqualsDeformAndChecksItsArguments) {
  Fixture f(2);
  f.edit.handles[0].manipulator.rotation = Manipulator::axis_angle(Vec3(0, 1, 0), 30);
  const EditSolver solver(f.mesh, f.edit);
  VertexData<Vec3> positions = f.mesh.positions();
  solver.evaluate(solver.transforms(f.edit), positions);
  const Mesh once = deform(f.mesh, f.edit);
  for (Vertex v : f.mesh.vertices()) EXPECT_EQ(positions[v], once.position(v)) << v.idx();
  EXPECT_EQ(solver.n_movable(), 1);
  EXPECT_EQ(solver.stats().deformation, Deformation::Linear);

  const std::vector<Eigen::Affine3d> none;
  EXPECT_THROW(solver.evaluate(none, positions), InvalidInput);
  Edit two = f.edit;
  two.handles.push_back(f.edit.handles[0]);
  EXPECT_THAT([&] { (void)solver.transforms(two); },
              ::testing::ThrowsMessage<InvalidInput>(HasSubstr("the edit has 2 movable handles, the solver 1")));
  const VertexData<Vec3> short_positions(3, Vec3::Zero());
  EXPECT_THROW((void)solver.problems(short_positions), InvalidInput);
}

TEST(EditSolver, NonFinitePositionsAreNamed) {
  Fixture f(2);
  const EditSolver solver(f.mesh, f.edit);
  VertexData<Vec3> positions = f.mesh.positions();
  solver.evaluate(solver.transforms(f.edit), positions);
  const Vertex bad = solver.touched()[3];
  positions[bad] = Vec3(std::nan(""), 0, 0);
  const EditProblems p = solver.problems(positions);
  EXPECT_EQ(p.non_finite, 1);
  EXPECT_EQ(p.first_non_finite, bad);
  EXPECT_THAT([&] { require_finite(p); },
              ::testing::ThrowsMessage<SolverError>(HasSubstr("the first at vertex " + std::to_string(bad.idx()))));
}

TEST(EditSolver, ProgressCancelsThePrecomputation) {
  Fixture f(3);
  std::atomic<bool> cancel{true};
  Progress progress;
  progress.cancel = &cancel;
  EXPECT_THROW(EditSolver(f.mesh, f.edit, progress), Cancelled);
  cancel = false;
  std::vector<std::string> stages;
  progress.report = [&](std::string_view stage, double) { stages.emplace_back(stage); };
  const EditSolver solver(f.mesh, f.edit, progress);
  EXPECT_FALSE(stages.empty());
  EXPECT_EQ(stages.back(), "detail");  // multiresolution last
}

// A closed sphere in the support with one movable handle and nothing fixed: the linear fill
// from the handle collapses the sphere, so it is refused with the way out; the nonlinear model
// (which keeps the rest shape) and an explicit "allow_unanchored" solve it.
TEST(EditSolver, UnanchoredClosedComponentIsRefusedUnlessAllowed) {
  const Mesh sphere = Mesh::from_soup(make_icosphere(2));
  const std::string text = R"({"support": {"sphere": {"center": [0, 0, 0], "radius": 10}},
      "handles": [{"region": {"sphere": {"center": [0, 0, 1], "radius": 0.3}},
                   "transform": {"translate": [0, 0, 0.2]}}]})";
  Edit edit = parse_edit_text(text, sphere, "sphere.json", ".");
  try {
    const EditSolver solver(sphere, edit);
    ADD_FAILURE() << "expected InvalidInput";
  } catch (const InvalidInput& e) {
    EXPECT_THAT(e.what(), HasSubstr("closed component"));
    EXPECT_THAT(e.what(), HasSubstr("allow_unanchored"));
  }
  edit.allow_unanchored = true;
  EXPECT_NO_THROW(EditSolver(sphere, edit));
  EXPECT_EQ(edit_to_json(edit)["allow_unanchored"], true);  // round trip of the option
  edit.allow_unanchored = false;
  edit.deformation = Deformation::Nonlinear;
  EXPECT_NO_THROW(EditSolver(sphere, edit));
  // One fixed vertex anchors it.
  Edit anchored = parse_edit_text(text, sphere, "sphere.json", ".");
  anchored.support.erase(anchored.support.begin());
  EXPECT_NO_THROW(EditSolver(sphere, anchored));
}

// A support vertex that no triangle uses stays put with a count, instead of failing the edit
// with "covers a whole component".
TEST(EditSolver, IsolatedSupportVerticesStayAndAreCounted) {
  TriangleSoup soup = make_plane(20, 20);
  soup.positions.push_back(Vec3(0.5, 0.7, 0.01));  // unreferenced, in the support, not in the handle
  const Mesh mesh = Mesh::from_soup(soup);
  const Edit edit = parse_edit_text(R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.31}},
      "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.11}},
                   "transform": {"translate": [0, 0, 0.2]}}]})", mesh, "test", ".");
  const Vertex isolated(mesh.n_vertices() - 1);
  ASSERT_TRUE(std::find(edit.support.begin(), edit.support.end(), isolated) != edit.support.end());
  const EditSolver solver(mesh, edit);
  EXPECT_EQ(solver.stats().isolated_ignored, 1);
  VertexData<Vec3> x = mesh.positions();
  solver.evaluate(solver.transforms(edit), x);
  EXPECT_EQ(x[isolated], mesh.position(isolated));
  EXPECT_GT(x[Vertex(10 * 21 + 10)].z(), 0.15);  // the centre moved with the handle
}
