// The one-shot deform() (bcm/edit.h): sanity on a flat grid for k = 1..3.
#include "freeform/bcm/edit.h"
#include "freeform/bcm/edit_file.h"
#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

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
  BcmStats stats;
  const Mesh out = deform(f.mesh, f.edit, &stats);
  ASSERT_EQ(out.n_vertices(), f.mesh.n_vertices());
  ASSERT_EQ(out.n_faces(), f.mesh.n_faces());
  EXPECT_FALSE(stats.solver.empty());
  EXPECT_GT(stats.free, 0);
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
  const Regions regions = edit_regions(f.mesh, f.edit);
  const BcmSolver solver(f.mesh, regions, f.edit.settings);
  const auto transforms = edit_transforms(f.edit, solver);
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
  fixed.fixed = true;
  fixed.vertices = {Vertex(10 * 21 + 14)};  // (0.7, 0.5): inside the support, held in place
  f.edit.handles.push_back(fixed);
  const Mesh out = deform(f.mesh, f.edit);
  EXPECT_EQ(out.position(fixed.vertices[0]), f.mesh.position(fixed.vertices[0]));
  for (Vertex v : f.edit.handles[0].vertices) EXPECT_LT((out.position(v) - f.mesh.position(v) - Vec3(0.05, 0, 0)).norm(), 1e-12);
}

TEST(Deform, RefusesWhatIsNotAvailableOrNotSolvable) {
  Fixture f(2);
  f.edit.anisotropic = true;  // available (tests/anisotropic): the edit goes through
  BcmStats stats;
  EXPECT_NO_THROW((void)deform(f.mesh, f.edit, &stats));
  EXPECT_TRUE(stats.anisotropic || !stats.anisotropic_fallback.empty());
  f.edit.anisotropic = false;

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
