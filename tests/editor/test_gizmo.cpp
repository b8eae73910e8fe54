// Gizmo shape and picking against independently projected 3D gizmo points; gizmo drags.
#include "editor/gizmo.h"

#include "freeform/common/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace freeform::editor {
namespace {

constexpr double kPi = std::numbers::pi;
const Vec3 kPivot(0.2, 0.1, -0.1);

ScreenView perspective_view() {
  ScreenView v;
  v.camera.eye = Vec3(3.0, -5.0, 2.5);
  v.camera.target = Vec3(0.1, 0.1, 0.0);
  v.camera.up = Vec3(0, 0, 1);
  v.camera.fov_y_deg = 35.0;
  v.width = 1000;
  v.height = 700;
  return v;
}

Manipulator start_manipulator() {
  Manipulator m;
  m.translation = Vec3(0.1, 0.05, 0.3);
  m.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.9, Vec3(0.3, -1, 0.6).normalized()));
  m.scale = Vec3(1.1, 0.9, 1.3);
  return m;
}

Eigen::Vector2d px(const ScreenView& v, const Vec3& p) { return v.project(p).value().head<2>(); }
double arm_world(const ScreenView& v, const Vec3& c) { return 100.0 * v.world_per_pixel(c); }

// Distance from a pixel to the projection of a 3D circle (dense sampling).
double ring_distance(const ScreenView& v, const Vec3& c, const Vec3& axis, double r, const Eigen::Vector2d& p) {
  const Vec3 u = axis.unitOrthogonal(), w = axis.cross(u);
  double best = 1e300;
  for (int k = 0; k < 2000; ++k) {
    const double a = 2 * kPi * k / 2000;
    best = std::min(best, (px(v, c + r * (std::cos(a) * u + std::sin(a) * w)) - p).norm());
  }
  return best;
}

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (p - (a + t * (b - a))).norm();
}

TEST(Gizmo, HitsArrowTipsBoxesCentreAndNothingFarAway) {
  const ScreenView view = perspective_view();
  const Manipulator m = start_manipulator();
  const Vec3 c = kPivot + m.translation;
  const GizmoShape shape = gizmo_shape(view, c, m.rotation);
  ASSERT_TRUE(shape.visible);
  const double arm = arm_world(view, c);
  const Eigen::Vector2d c_px = px(view, c);
  const Eigen::Matrix3d local = m.rotation.toRotationMatrix();
  EXPECT_EQ(gizmo_hit(shape, c_px), GizmoPart::Center);
  EXPECT_EQ(gizmo_hit(shape, c_px + Eigen::Vector2d(5, -4)), GizmoPart::Center);
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d tip = px(view, c + arm * Vec3::Unit(i));
    const Eigen::Vector2d dir = (tip - c_px).normalized();
    ASSERT_GT((tip - c_px).norm(), 30.0);  // no axis points at the eye in this view
    EXPECT_EQ(gizmo_hit(shape, tip - 4.0 * dir), static_cast<GizmoPart>(static_cast<int>(GizmoPart::MoveX) + i));
    // The far end of an arm line, away from boxes and rings.
    const Eigen::Vector2d box = px(view, c + kGizmoBoxAt * arm * Vec3(local.col(i)));
    EXPECT_EQ(gizmo_hit(shape, box), static_cast<GizmoPart>(static_cast<int>(GizmoPart::ScaleX) + i)) << i;
  }
  EXPECT_EQ(gizmo_hit(shape, c_px + Eigen::Vector2d(300, 250)), GizmoPart::None);
  EXPECT_EQ(gizmo_hit(shape, Eigen::Vector2d(-50, -50)), GizmoPart::None);
}

TEST(Gizmo, HitsRingsWhereNothingElseIsNear) {
  const ScreenView view = perspective_view();
  const Vec3 c(0.3, -0.2, 0.1);
  const GizmoShape shape = gizmo_shape(view, c);
  const double arm = arm_world(view, c), r = kGizmoRingRadius * arm;
  const Eigen::Vector2d c_px = px(view, c);
  for (int i = 0; i < 3; ++i) {
    const Vec3 axis = Vec3::Unit(i), u = axis.unitOrthogonal(), w = axis.cross(u);
    int clean = 0;
    for (int k = 0; k < 72; ++k) {
      const double a = 2 * kPi * k / 72;
      const Eigen::Vector2d p = px(view, c + r * (std::cos(a) * u + std::sin(a) * w));
      // Skip points that another part could win: near the centre, an arrowhead or a box (these
      // come first), or another ring (the nearest ring wins). Arm lines come after rings.
      bool near_other = (p - c_px).norm() < 25.0;
      for (int j = 0; j < 3; ++j) {
        near_other |= (p - px(view, c + arm * Vec3::Unit(j))).norm() < 28.0;
        near_other |= (p - px(view, c + kGizmoBoxAt * arm * Vec3::Unit(j))).norm() < 20.0;
        if (j != i) near_other |= ring_distance(view, c, Vec3::Unit(j), r, p) < 8.0;
      }
      if (near_other) continue;
      ++clean;
      EXPECT_EQ(gizmo_hit(shape, p + Eigen::Vector2d(2, -2)),
                static_cast<GizmoPart>(static_cast<int>(GizmoPart::RotateX) + i))
          << "ring " << i << " angle " << k * 5;
    }
    EXPECT_GE(clean, 8) << "ring " << i;
  }
}

TEST(Gizmo, RingBeatsArmLineWhereTheyCross) {
  const ScreenView view = perspective_view();
  const Vec3 c(0.3, -0.2, 0.1);
  const GizmoShape shape = gizmo_shape(view, c);
  // The two other rings cross each arm at kGizmoRingRadius of its length; take the longest arm on screen so
  // the crossing is outside its arrowhead (16 px long, plus the 6 px tolerance).
  const double arm = arm_world(view, c);
  const Eigen::Vector2d c_px = px(view, c);
  int longest = 0;
  for (int i = 1; i < 3; ++i)
    if ((px(view, c + arm * Vec3::Unit(i)) - c_px).norm() > (px(view, c + arm * Vec3::Unit(longest)) - c_px).norm())
      longest = i;
  const Eigen::Vector2d cross = px(view, c + kGizmoRingRadius * arm * Vec3::Unit(longest));
  ASSERT_GT((px(view, c + arm * Vec3::Unit(longest)) - cross).norm(), 22.0);
  ASSERT_LT(segment_distance(cross, c_px, px(view, c + arm * Vec3::Unit(longest))), 1e-9);  // on the arm line
  const GizmoPart hit = gizmo_hit(shape, cross);
  const int h = static_cast<int>(hit) - static_cast<int>(GizmoPart::RotateX);
  EXPECT_TRUE(h >= 0 && h < 3 && h != longest) << static_cast<int>(hit);
}

TEST(Gizmo, AxisPointingAtTheEyeDoesNotStealClicks) {
  const Vec3 c(0.3, -0.2, 0.1);
  ScreenView view = perspective_view();
  view.camera.target = c;
  view.camera.eye = c + Vec3(5.0, 0.02, 0.01);  // looking almost exactly down -X
  const GizmoShape shape = gizmo_shape(view, c);
  ASSERT_TRUE(shape.visible);
  ASSERT_LT((px(view, c + arm_world(view, c) * Vec3::UnitX()) - px(view, c)).norm(), 10.0);
  for (const auto& a : shape.arms) EXPECT_NE(a.part, GizmoPart::MoveX);
  for (const auto& a : shape.arrowheads) EXPECT_NE(a.part, GizmoPart::MoveX);
  for (const auto& b : shape.boxes) EXPECT_NE(b.part, GizmoPart::ScaleX);
  const Eigen::Vector2d c_px = px(view, c);
  for (int k = 0; k < 72; ++k) {
    for (double rad : {3.0, 12.0, 20.0, 40.0}) {
      const double a = 2 * kPi * k / 72;
      const GizmoPart hit = gizmo_hit(shape, c_px + rad * Eigen::Vector2d(std::cos(a), std::sin(a)));
      EXPECT_NE(hit, GizmoPart::MoveX);
      EXPECT_NE(hit, GizmoPart::ScaleX);
    }
  }
  EXPECT_EQ(gizmo_hit(shape, c_px + Eigen::Vector2d(2, 1)), GizmoPart::Center);
  // The X ring faces the viewer: a circle of radius kGizmoRingRadius * 100 px that still hits.
  const double ring_px = kGizmoRingRadius * 100.0;
  EXPECT_EQ(gizmo_hit(shape, c_px + ring_px * Eigen::Vector2d(-std::cos(0.5), std::sin(0.5))), GizmoPart::RotateX);
}

TEST(Gizmo, HoveredPartIsHighlightedAndRingsHaveBackPieces) {
  const ScreenView view = perspective_view();
  const GizmoPalette palette;
  const GizmoShape shape = gizmo_shape(view, Vec3(0, 0, 0), Eigen::Quaterniond::Identity(), 100, GizmoPart::RotateY);
  int front = 0, back = 0;
  for (const auto& r : shape.rings) {
    const bool hovered = r.color.r == palette.hovered.r && r.color.g == palette.hovered.g;
    EXPECT_EQ(hovered, r.part == GizmoPart::RotateY);
    (r.front ? front : back)++;
  }
  EXPECT_GE(front, 3);
  EXPECT_GE(back, 3);
  EXPECT_FALSE(shape.rings.front().front);  // back pieces are drawn first
  EXPECT_THROW(gizmo_shape(view, Vec3(0, 0, 0), Eigen::Quaterniond::Identity(), 0.0), InvalidInput);
}

TEST(Gizmo, BehindTheEyeIsInvisible) {
  const ScreenView view = perspective_view();
  const Vec3 behind = view.camera.eye - 2.0 * view.forward();
  const GizmoShape shape = gizmo_shape(view, behind);
  EXPECT_FALSE(shape.visible);
  EXPECT_EQ(gizmo_hit(shape, Eigen::Vector2d(500, 350)), GizmoPart::None);
}

TEST(GizmoDrag, MoveXMovesOnlyAlongX) {
  const ScreenView view = perspective_view();
  const Manipulator start = start_manipulator();
  const Vec3 c = kPivot + start.translation;
  const Eigen::Vector2d tip = px(view, c + arm_world(view, c) * Vec3::UnitX());
  GizmoDrag drag(GizmoPart::MoveX, start, kPivot, view, tip);
  drag.move_mouse(tip + Eigen::Vector2d(45, 70));
  const Manipulator m = drag.current();
  const Vec3 d = m.translation - start.translation;
  EXPECT_GT(std::abs(d.x()), 1e-3);
  EXPECT_EQ(d.y(), 0.0);
  EXPECT_EQ(d.z(), 0.0);
  EXPECT_EQ(m.rotation.coeffs(), start.rotation.coeffs());
  EXPECT_EQ(m.scale, start.scale);
  EXPECT_EQ(drag.cancel().translation, start.translation);
}

TEST(GizmoDrag, RotateZTurnsAboutWorldZ) {
  const ScreenView view = perspective_view();
  const Manipulator start = start_manipulator();
  const Eigen::Vector2d c_px = px(view, kPivot + start.translation);
  GizmoDrag drag(GizmoPart::RotateZ, start, kPivot, view, c_px + Eigen::Vector2d(80, 0));
  drag.move_mouse(c_px + Eigen::Vector2d(0, -80));  // a quarter turn counter-clockwise as seen
  const Eigen::Matrix3d rd = drag.current().rotation.toRotationMatrix() * start.rotation.toRotationMatrix().transpose();
  EXPECT_LT((rd - Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()).toRotationMatrix()).norm(), 1e-12);
  EXPECT_EQ(drag.current().translation, start.translation);
}

TEST(GizmoDrag, ScaleXScalesLocalXAndCentreGrabsFreely) {
  const ScreenView view = perspective_view();
  const Manipulator start = start_manipulator();
  const Vec3 c = kPivot + start.translation;
  const Eigen::Vector2d c_px = px(view, c);
  const Eigen::Vector2d box =
      px(view, c + kGizmoBoxAt * arm_world(view, c) * Vec3(start.rotation.toRotationMatrix().col(0)));
  GizmoDrag drag(GizmoPart::ScaleX, start, kPivot, view, box);
  drag.move_mouse(c_px + 3.0 * (box - c_px));
  EXPECT_NEAR(drag.current().scale.x(), 3.0 * start.scale.x(), 1e-12);
  EXPECT_EQ(drag.current().scale.y(), start.scale.y());
  EXPECT_EQ(drag.current().scale.z(), start.scale.z());

  GizmoDrag grab(GizmoPart::Center, start, kPivot, view, c_px);
  grab.move_mouse(c_px + Eigen::Vector2d(-25, 40));
  EXPECT_LT((px(view, kPivot + grab.current().translation) - (c_px + Eigen::Vector2d(-25, 40))).norm(), 1e-9);
  EXPECT_THROW(GizmoDrag(GizmoPart::None, start, kPivot, view, c_px), InvalidInput);
}

}  // namespace
}  // namespace freeform::editor
