// FramePrecision::Display against the exact frame: within 1e-6 of the bounding-box diagonal
// (issue 13's bound for float display frames) for large rotations, translations and scales,
// small handles far from the support's centre, meshes far from the origin and many handles;
// identical at rest.
#include "bcm_fixtures.h"

#include "freeform/mesh/bounds.h"

#include <numbers>

namespace freeform::test {
namespace {

// A 90 x 90 bumpy plane (> 4096 free rows: the parallel path) moved by `offset`; a centre
// handle and a single-vertex handle near the support's rim, both movable.
struct FarScene {
  Mesh mesh;
  Regions regions;
  explicit FarScene(const Vec3& offset) : mesh(make(offset)), regions(build(mesh, offset)) {}
  static Mesh make(const Vec3& offset) {
    TriangleSoup soup = make_bumpy_plane(90, 90, 0.05, 1.0);
    for (Vec3& p : soup.positions) p += offset;
    return Mesh::from_soup(soup);
  }
  static Regions build(const Mesh& mesh, const Vec3& offset) {
    std::vector<Vertex> support, centre, rim;
    for (Vertex v : mesh.vertices()) {
      const Vec3 p = mesh.position(v) - offset;
      if ((p - Vec3(0.5, 0.5, 0)).head<2>().norm() < 0.45) support.push_back(v);
      if ((p - Vec3(0.5, 0.5, 0)).head<2>().norm() < 0.04) centre.push_back(v);
    }
    double best = 1e300;
    Vertex nearest;
    for (Vertex v : support)
      if (const double d = (mesh.position(v) - offset - Vec3(0.2, 0.5, 0)).head<2>().norm(); d < best) {
        best = d;
        nearest = v;
      }
    rim.push_back(nearest);
    return Regions(mesh, support, {{centre, true}, {rim, true}});
  }
};

Eigen::Affine3d about(const Vec3& pivot, const Eigen::Matrix3d& linear, const Vec3& translation) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.linear() = linear;
  t.translation() = pivot - linear * pivot + translation;
  return t;
}

double display_error(const BcmSolver& solver, const std::vector<Eigen::Affine3d>& t, double diagonal) {
  RowMatrix exact(solver.n_free(), 3), display(solver.n_free(), 3);
  solver.evaluate(t, exact);
  solver.evaluate(t, display, FramePrecision::Display);
  return (exact - display).rowwise().norm().maxCoeff() / diagonal;
}

TEST(DisplayFrames, AtRestTheyAreTheExactFrame) {
  const FarScene scene(Vec3::Zero());
  const BcmSolver solver(scene.mesh, scene.regions, BcmSettings{});
  const std::vector<Eigen::Affine3d> rest(2, Eigen::Affine3d::Identity());
  RowMatrix exact(solver.n_free(), 3), display(solver.n_free(), 3);
  solver.evaluate(rest, exact);
  solver.evaluate(rest, display, FramePrecision::Display);
  EXPECT_EQ((exact - display).cwiseAbs().maxCoeff(), 0.0);
}

TEST(DisplayFrames, WithinAMillionthOfTheDiagonalForLargeMotions) {
  for (const int k : {2, 3})
    for (const Vec3& offset : {Vec3(0, 0, 0), Vec3(1e6, -2e6, 5e5)}) {
      const FarScene scene(offset);
      BcmSettings s;
      s.order = k;
      const BcmSolver solver(scene.mesh, scene.regions, s);
      ASSERT_GT(solver.n_free(), 5000);
      const double diagonal = bounding_diagonal(scene.mesh.positions());
      const Vec3 c0 = solver.handle_centroid(0), c1 = solver.handle_centroid(1);
      const Eigen::Matrix3d half_turn = Eigen::AngleAxisd(std::numbers::pi, Vec3(1, 1, 0).normalized()).toRotationMatrix();
      const Eigen::Matrix3d quarter = Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()).toRotationMatrix();
      const Vec3 across = diagonal * Vec3(0.6, -0.3, 0.74).normalized();
      const std::vector<std::vector<Eigen::Affine3d>> edits = {
          {about(c0, Eigen::Matrix3d::Identity(), across), Eigen::Affine3d::Identity()},     // translate a diagonal
          {about(c0, half_turn, Vec3::Zero()), about(c1, quarter, Vec3::Zero())},             // 180 and 90 degrees
          {about(c0, 2.0 * Eigen::Matrix3d::Identity(), Vec3::Zero()), about(c1, half_turn, -across)},  // scale 2
          {Eigen::Affine3d::Identity(), about(c1, 0.5 * quarter, across)},  // the single vertex
      };
      for (std::size_t e = 0; e < edits.size(); ++e) {
        const double err = display_error(solver, edits[e], diagonal);
        EXPECT_LT(err, 1e-6) << "k = " << k << ", offset " << offset.transpose() << ", edit " << e;
        EXPECT_GT(err, 0.0) << "the display frame must be the float basis, not the exact one";
      }
    }
}

TEST(DisplayFrames, ManyHandlesAndTheMeshPositionsOverload) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(30, 30, 0.06, 1.0));
  std::vector<HandleRegion> handles;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) handles.push_back({within(mesh, Vec3(0.2 + 0.1 * i, 0.2 + 0.1 * j, 0), 0.01), true});
  const Regions regions(mesh, within(mesh, Vec3(0.5, 0.5, 0), 0.45), handles);
  ASSERT_GT(regions.n_movable(), BcmSolver::kStackHandles);  // the dynamic kernel and the frame buffer
  BcmSettings s;
  s.order = 2;
  const BcmSolver solver(mesh, regions, s);
  std::mt19937 rng(31);
  std::vector<Eigen::Affine3d> t;
  for (int m = 0; m < regions.n_movable(); ++m) t.push_back(random_affine(rng));
  const double diagonal = bounding_diagonal(mesh.positions());
  EXPECT_LT(display_error(solver, t, diagonal), 1e-6);
  VertexData<Vec3> exact = mesh.positions(), display = mesh.positions();
  solver.evaluate(t, exact);
  solver.evaluate(t, display, FramePrecision::Display);
  double worst = 0.0;
  for (Vertex v : mesh.vertices()) worst = std::max(worst, (exact[v] - display[v]).norm());
  EXPECT_LT(worst / diagonal, 1e-6);
  for (Vertex v : mesh.vertices())
    if (regions.role(v) == Role::Fixed) {
      EXPECT_EQ(display[v], mesh.position(v));
    }
}

}  // namespace
}  // namespace freeform::test
