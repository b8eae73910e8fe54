// Camera navigation: orbit keeps the distance, pan translates eye and target together and
// keeps the grabbed point under the cursor, zoom scales the distance and never passes the
// target, fit frames the box (checked by projecting its corners through the camera matrices).
#include "editor/camera_controller.h"
#include "editor/screen.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

using namespace freeform;
using namespace freeform::editor;

namespace {

viewer::BoundingBox box() { return {{-1.0, -0.5, 0.0}, {2.0, 1.5, 0.8}}; }

std::vector<Eigen::Vector3d> corners(const viewer::BoundingBox& b) {
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < 8; ++i)
    out.emplace_back(i & 1 ? b.max.x() : b.min.x(), i & 2 ? b.max.y() : b.min.y(), i & 4 ? b.max.z() : b.min.z());
  return out;
}

Eigen::Vector3d ndc(const viewer::Camera& c, double aspect, const Eigen::Vector3d& p) {
  const Eigen::Vector4d q = c.projection(aspect) * c.view() * p.homogeneous();
  return q.head<3>() / q.w();
}

CameraController iso_controller() {
  CameraController cc;
  cc.reset(box(), viewer::ViewPreset::Iso, viewer::UpAxis::Z, 1.5);
  return cc;
}

double angle_to_axis(const CameraController& cc) {
  const Eigen::Vector3d o = (cc.camera().eye - cc.camera().target).normalized();
  return std::acos(std::clamp(o.dot(cc.up_axis()), -1.0, 1.0));
}

}  // namespace

TEST(CameraController, OrbitKeepsDistanceAndTarget) {
  CameraController cc = iso_controller();
  const double d0 = cc.distance();
  const Eigen::Vector3d t0 = cc.camera().target;
  const double moves[][2] = {{10, 0}, {0, 25}, {-300, 140}, {17, -900}, {5000, 5000}};
  for (const auto& m : moves) {
    cc.orbit(m[0], m[1]);
    EXPECT_NEAR(cc.distance(), d0, 1e-12 * d0);
    EXPECT_NEAR((cc.camera().target - t0).norm(), 0.0, 1e-15);
    EXPECT_TRUE(cc.camera().view().allFinite());
  }
}

TEST(CameraController, HorizontalOrbitIsAYawAroundTheUpAxis) {
  CameraController cc = iso_controller();
  const Eigen::Vector3d a = cc.up_axis();
  const Eigen::Vector3d o0 = cc.camera().eye - cc.camera().target;
  const double dx = 40.0;
  cc.orbit(dx, 0.0);
  const Eigen::Vector3d o1 = cc.camera().eye - cc.camera().target;
  EXPECT_NEAR(o1.dot(a), o0.dot(a), 1e-12);  // same height above the target
  const Eigen::Vector3d h0 = o0 - o0.dot(a) * a, h1 = o1 - o1.dot(a) * a;
  const double turned = std::atan2(h0.cross(h1).dot(a), h0.dot(h1));
  EXPECT_NEAR(turned, -dx * CameraController::kOrbitRadiansPerPixel, 1e-12);
}

TEST(CameraController, VerticalOrbitStopsShortOfThePoles) {
  CameraController cc = iso_controller();
  const double before = angle_to_axis(cc);
  cc.orbit(0.0, 10.0);  // dragging down lifts the eye towards the up axis
  EXPECT_NEAR(angle_to_axis(cc), before - 10.0 * CameraController::kOrbitRadiansPerPixel, 1e-12);
  cc.orbit(0.0, 1e6);
  EXPECT_GT(angle_to_axis(cc), 0.0);
  EXPECT_LT(angle_to_axis(cc), 0.02);
  cc.orbit(0.0, -1e6);
  EXPECT_LT(angle_to_axis(cc), std::numbers::pi);
  EXPECT_GT(angle_to_axis(cc), std::numbers::pi - 0.02);
  EXPECT_TRUE(cc.camera().view().allFinite());
}

TEST(CameraController, PanMovesEyeAndTargetTogetherAndTheGrabbedPointFollowsTheCursor) {
  CameraController cc = iso_controller();
  const viewer::Camera before = cc.camera();
  ScreenView screen{before, 900, 600};
  const auto p0 = screen.project(before.target);
  ASSERT_TRUE(p0);
  cc.pan(37.0, -21.0, screen.height);
  const viewer::Camera& after = cc.camera();
  const Eigen::Vector3d de = after.eye - before.eye, dt = after.target - before.target;
  EXPECT_NEAR((de - dt).norm(), 0.0, 1e-12);
  EXPECT_GT(dt.norm(), 0.0);
  EXPECT_NEAR(dt.dot((before.target - before.eye).normalized()), 0.0, 1e-12);  // in the view plane
  screen.camera = after;
  const auto p1 = screen.project(before.target);
  ASSERT_TRUE(p1);
  EXPECT_NEAR(p1->x() - p0->x(), 37.0, 1e-6);
  EXPECT_NEAR(p1->y() - p0->y(), -21.0, 1e-6);
}

TEST(CameraController, ZoomScalesTheDistanceAlongTheViewDirection) {
  CameraController cc = iso_controller();
  const double d0 = cc.distance();
  const Eigen::Vector3d dir0 = (cc.camera().eye - cc.camera().target).normalized();
  cc.zoom(0.5);
  EXPECT_NEAR(cc.distance(), 0.5 * d0, 1e-12 * d0);
  cc.zoom(3.0);
  EXPECT_NEAR(cc.distance(), 1.5 * d0, 1e-12 * d0);
  cc.wheel(2.0);
  EXPECT_NEAR(cc.distance(), 1.5 * d0 * CameraController::kWheelFactor * CameraController::kWheelFactor, 1e-12 * d0);
  EXPECT_NEAR(((cc.camera().eye - cc.camera().target).normalized() - dir0).norm(), 0.0, 1e-12);
}

TEST(CameraController, ZoomNeverReachesOrPassesTheTarget) {
  CameraController cc = iso_controller();
  const Eigen::Vector3d dir0 = (cc.camera().eye - cc.camera().target).normalized();
  for (int i = 0; i < 200; ++i) cc.zoom(0.3);
  EXPECT_GE(cc.distance(), cc.min_distance() * (1 - 1e-12));
  EXPECT_GT(cc.distance(), 0.0);
  EXPECT_GT((cc.camera().eye - cc.camera().target).dot(dir0), 0.0);  // still on the same side
  const double d = cc.distance();
  cc.zoom(0.0);
  cc.zoom(-2.0);
  cc.zoom(std::nan(""));
  EXPECT_EQ(cc.distance(), d);
  EXPECT_TRUE(cc.camera().projection(1.0).allFinite());
  EXPECT_GT(cc.camera().z_near, 0.0);
}

TEST(CameraController, FitKeepsTheDirectionAndFramesEveryCorner) {
  const double margin = 1.08;
  for (double aspect : {0.5, 1.0, 2.2}) {
    CameraController cc = iso_controller();
    cc.orbit(123.0, -45.0);
    cc.pan(300.0, 80.0, 600);
    cc.zoom(7.0);
    const Eigen::Vector3d dir0 = (cc.camera().eye - cc.camera().target).normalized();
    cc.fit(box(), aspect, margin);
    const viewer::Camera& c = cc.camera();
    EXPECT_NEAR(((c.eye - c.target).normalized() - dir0).norm(), 0.0, 1e-12);
    EXPECT_NEAR((c.target - box().center()).norm(), 0.0, 1e-12);
    double extent = 0.0;
    for (const auto& p : corners(box())) {
      const Eigen::Vector3d q = ndc(c, aspect, p);
      EXPECT_LE(std::abs(q.x()), 1.0 / margin + 1e-9) << aspect;
      EXPECT_LE(std::abs(q.y()), 1.0 / margin + 1e-9) << aspect;
      EXPECT_GT(q.z(), -1.0);  // between the clip planes
      EXPECT_LT(q.z(), 1.0);
      extent = std::max({extent, std::abs(q.x()), std::abs(q.y())});
    }
    EXPECT_NEAR(extent, 1.0 / margin, 1e-9) << "not the tightest fit, aspect " << aspect;
  }
}

TEST(CameraController, ResetLooksAlongThePresetWithTheChosenUpAxis) {
  CameraController cc;
  cc.reset(box(), viewer::ViewPreset::Front, viewer::UpAxis::Y, 1.0);
  const Eigen::Vector3d dir = (cc.camera().eye - cc.camera().target).normalized();
  EXPECT_NEAR((dir - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);  // y up: the front eye is on +z
  EXPECT_NEAR((cc.up_axis() - Eigen::Vector3d::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_GT(ndc(cc.camera(), 1.0, box().center() + Eigen::Vector3d(0, 0.5, 0)).y(), 0.05);  // +y is up
}

TEST(CameraController, ClipPlanesFollowTheBounds) {
  CameraController cc = iso_controller();
  viewer::BoundingBox big{{-50, -50, -50}, {50, 50, 50}};
  cc.set_bounds(big);
  for (const auto& p : corners(big)) {
    const Eigen::Vector3d q = ndc(cc.camera(), 1.5, p);
    if ((p - cc.camera().eye).dot(cc.camera().target - cc.camera().eye) > 0) {
      EXPECT_LE(q.z(), 1.0);
    }
  }
  EXPECT_GE(cc.camera().z_far, (big.center() - cc.camera().eye).norm() + big.radius());
}
