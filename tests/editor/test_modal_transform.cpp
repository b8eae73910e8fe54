// Modal grab / rotate / scale: typed amounts against closed forms, mouse drags against
// independent projections of the result.
#include "editor/modal_transform.h"

#include "freeform/common/error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace freeform::editor {
namespace {

constexpr double kPi = std::numbers::pi;

ScreenView perspective_view() {
  ScreenView v;
  v.camera.eye = Vec3(2.0, -5.0, 3.0);
  v.camera.target = Vec3(0.3, 0.2, 0.1);
  v.camera.up = Vec3(0, 0, 1);
  v.camera.fov_y_deg = 40.0;
  v.width = 800;
  v.height = 600;
  return v;
}

const Vec3 kPivot(0.2, 0.1, -0.1);

Manipulator rotated_start() {
  Manipulator m;
  m.translation = Vec3(0.1, -0.2, 0.3);
  m.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()));
  m.scale = Vec3(1.2, 0.8, 1.5);
  return m;
}

Eigen::Matrix3d rot(const Manipulator& m) { return m.rotation.normalized().toRotationMatrix(); }
Vec3 centre(const Manipulator& m) { return kPivot + m.translation; }
Eigen::Vector2d px(const ScreenView& v, const Vec3& p) { return v.project(p).value().head<2>(); }
Vec3 apply(const Manipulator& m, const Vec3& x) { return m.to_affine(kPivot) * x; }

void expect_same_rs(const Manipulator& a, const Manipulator& b) {
  EXPECT_EQ(a.rotation.coeffs(), b.rotation.coeffs());
  EXPECT_EQ(a.scale, b.scale);
}

void type(ModalTransform& t, const std::string& s) {
  for (char c : s) EXPECT_TRUE(t.type_char(c)) << c;
}

TEST(ModalTransform, GrabTypedAlongGlobalX) {
  Manipulator start;
  start.translation = Vec3(0.1, -0.2, 0.3);
  const ScreenView view = perspective_view();
  ModalTransform t(TransformKind::Grab, start, kPivot, view, {400, 300});
  t.move_mouse({430, 250});  // typed numbers override the mouse
  t.press_axis(0);
  type(t, "2.5");
  const Manipulator m = t.confirm();
  EXPECT_EQ(m.translation, Vec3(start.translation + Vec3(2.5, 0, 0)));
  expect_same_rs(m, start);
  EXPECT_EQ(t.status(), "Grab  X (global): 2.5");
}

TEST(ModalTransform, GrabTypedAlongLocalXOfRotatedHandle) {
  const Manipulator start = rotated_start();
  ModalTransform t(TransformKind::Grab, start, kPivot, perspective_view(), {400, 300});
  t.press_axis(0);
  t.press_axis(0);
  EXPECT_EQ(t.axis(), AxisLock::LocalX);
  type(t, "2.5");
  const Manipulator m = t.current();
  EXPECT_LT((m.translation - (start.translation + 2.5 * rot(start).col(0))).norm(), 1e-14);
  expect_same_rs(m, start);
  EXPECT_EQ(t.status(), "Grab  X (local): 2.5");
}

TEST(ModalTransform, GrabTypedWithoutLockMovesAlongX) {
  const Manipulator start = rotated_start();
  ModalTransform t(TransformKind::Grab, start, kPivot, perspective_view(), {400, 300});
  type(t, "-1");
  EXPECT_EQ(t.current().translation, Vec3(start.translation - Vec3(1, 0, 0)));
}

TEST(ModalTransform, RotateTypedAboutGlobalZKeepsCentre) {
  const Manipulator start = rotated_start();
  ModalTransform t(TransformKind::Rotate, start, kPivot, perspective_view(), {400, 300});
  t.press_axis(2);
  type(t, "90");
  const Manipulator m = t.confirm();
  const Eigen::Matrix3d rz = Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_LT((rot(m) - rz * rot(start)).norm(), 1e-12);
  EXPECT_EQ(m.translation, start.translation);
  EXPECT_EQ(m.scale, start.scale);
  // Every deformed point turns by 90 degrees about the centre, which stays put.
  const Vec3 c = centre(start);
  EXPECT_LT((apply(m, kPivot) - c).norm(), 1e-12);
  for (const Vec3& x : {Vec3(1, 0, 0), Vec3(-0.3, 0.7, 0.2), Vec3(0.5, 0.5, -1)})
    EXPECT_LT((apply(m, x) - (c + rz * (apply(start, x) - c))).norm(), 1e-12);
  EXPECT_EQ(t.status(), "Rotate  Z (global): 90\xC2\xB0");
}

TEST(ModalTransform, RotateTypedAboutViewAxisIsCounterClockwiseAsSeen) {
  const ScreenView view = perspective_view();
  const Manipulator start = rotated_start();
  ModalTransform t(TransformKind::Rotate, start, kPivot, view, {400, 300});
  type(t, "30");
  const Eigen::Matrix3d rd = Eigen::AngleAxisd(kPi / 6, -view.forward()).toRotationMatrix();
  EXPECT_LT((rot(t.current()) - rd * rot(start)).norm(), 1e-12);
}

TEST(ModalTransform, ScaleTypedAlongY) {
  const Manipulator start = rotated_start();
  ModalTransform t(TransformKind::Scale, start, kPivot, perspective_view(), {400, 300});
  t.press_axis(1);
  EXPECT_EQ(t.axis(), AxisLock::LocalY);  // scale locks are always local
  type(t, "2");
  const Manipulator m = t.current();
  EXPECT_EQ(m.scale, Vec3(start.scale.x(), 2 * start.scale.y(), start.scale.z()));
  EXPECT_EQ(m.translation, start.translation);
  EXPECT_EQ(m.rotation.coeffs(), start.rotation.coeffs());
  // Geometrically: a stretch by 2 along the handle's local Y about the current centre.
  const Vec3 c = centre(start), ly = rot(start).col(1);
  for (const Vec3& x : {Vec3(1, 0, 0), Vec3(-0.3, 0.7, 0.2)}) {
    const Vec3 d = apply(start, x) - c;
    EXPECT_LT((apply(m, x) - (c + d + d.dot(ly) * ly)).norm(), 1e-12);
  }
  EXPECT_EQ(t.status(), "Scale  Y (local): 2");
  t.press_axis(1);
  EXPECT_EQ(t.axis(), AxisLock::None);
  EXPECT_LT((t.current().scale - 2 * start.scale).norm(), 1e-15);
  t.set_axis(AxisLock::GlobalZ);
  EXPECT_EQ(t.axis(), AxisLock::LocalZ);
}

TEST(ModalTransform, AxisKeysCycle) {
  ModalTransform t(TransformKind::Grab, Manipulator{}, kPivot, perspective_view(), {400, 300});
  EXPECT_EQ(t.axis(), AxisLock::None);
  t.press_axis(0);
  EXPECT_EQ(t.axis(), AxisLock::GlobalX);
  t.press_axis(0);
  EXPECT_EQ(t.axis(), AxisLock::LocalX);
  t.press_axis(0);
  EXPECT_EQ(t.axis(), AxisLock::None);
  t.press_axis(0);
  t.press_axis(1);
  EXPECT_EQ(t.axis(), AxisLock::GlobalY);
  t.press_axis(1);
  t.press_axis(2);
  EXPECT_EQ(t.axis(), AxisLock::GlobalZ);
  EXPECT_THROW(t.press_axis(3), InvalidInput);
}

TEST(ModalTransform, TypingSignAndBackspace) {
  const Manipulator start = rotated_start();
  ModalTransform t(TransformKind::Grab, start, kPivot, perspective_view(), {400, 300});
  t.press_axis(0);
  auto dx = [&] { return t.current().translation.x() - start.translation.x(); };
  EXPECT_FALSE(t.typed_active());
  EXPECT_FALSE(t.type_char('a'));
  type(t, "2");
  EXPECT_TRUE(t.type_char('-'));
  EXPECT_NEAR(dx(), -2.0, 1e-15);
  type(t, ".5");
  EXPECT_NEAR(dx(), -2.5, 1e-15);
  EXPECT_EQ(t.typed_text(), "-2.5");
  EXPECT_FALSE(t.type_char('.'));  // a second point
  EXPECT_TRUE(t.type_char('-'));
  EXPECT_NEAR(dx(), 2.5, 1e-15);
  t.backspace();
  EXPECT_NEAR(dx(), 2.0, 1e-15);  // "2."
  t.backspace();
  t.backspace();  // empty: back to the mouse, which has not moved
  EXPECT_FALSE(t.typed_active());
  EXPECT_EQ(t.current().translation, start.translation);
  type(t, "-");
  EXPECT_FALSE(t.typed_active());  // a sign alone is no number
  EXPECT_EQ(t.status().find("Grab  X (global): - (mouse"), 0u);
  t.backspace();
  EXPECT_EQ(t.typed_text(), "");
  type(t, ".");
  EXPECT_FALSE(t.typed_active());
  type(t, "25");
  EXPECT_NEAR(dx(), 0.25, 1e-15);
}

TEST(ModalTransform, CancelReturnsStartExactly) {
  Manipulator start = rotated_start();
  start.pivot = Vec3(1, 2, 3);
  ModalTransform t(TransformKind::Rotate, start, *start.pivot, perspective_view(), {400, 300});
  t.move_mouse({500, 100});
  type(t, "33");
  const Manipulator& c = t.cancel();
  EXPECT_EQ(c.translation, start.translation);
  EXPECT_EQ(c.rotation.coeffs(), start.rotation.coeffs());
  EXPECT_EQ(c.scale, start.scale);
  EXPECT_EQ(c.pivot, start.pivot);
  EXPECT_EQ(t.current().pivot, start.pivot);
}

TEST(ModalTransform, FreeGrabFollowsTheMouseExactly) {
  const ScreenView view = perspective_view();
  const Manipulator start = rotated_start();
  const Eigen::Vector2d c_px = px(view, centre(start));
  const Eigen::Vector2d m0 = c_px + Eigen::Vector2d(13, -7);  // grabbed off-centre
  ModalTransform t(TransformKind::Grab, start, kPivot, view, m0);
  for (const Eigen::Vector2d& d :
       {Eigen::Vector2d(37.5, -22.25), Eigen::Vector2d(-150, 80), Eigen::Vector2d(0.3, 0.1)}) {
    t.move_mouse(m0 + d);
    const Manipulator m = t.current();
    EXPECT_LT((px(view, centre(m)) - (c_px + d)).norm(), 1e-9);
    EXPECT_NEAR((centre(m) - centre(start)).dot(view.forward()), 0.0, 1e-12);  // same depth plane
    expect_same_rs(m, start);
  }
}

TEST(ModalTransform, AxisGrabStaysOnTheAxisUnderTheMouse) {
  const ScreenView view = perspective_view();
  const Manipulator start = rotated_start();
  const Vec3 c0 = centre(start);
  const Eigen::Vector2d c_px = px(view, c0);
  struct Case {
    int presses;
    Vec3 axis;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (const Case& k : {Case{1, Vec3::Unit(axis)}, Case{2, rot(start).col(axis)}}) {
      ModalTransform t(TransformKind::Grab, start, kPivot, view, c_px);
      for (int i = 0; i < k.presses; ++i) t.press_axis(axis);
      const Eigen::Vector2d mouse = c_px + Eigen::Vector2d(57, -31);
      t.move_mouse(mouse);
      const Vec3 c = centre(t.current());
      // On the axis line through the start centre.
      const Vec3 off = c - c0;
      EXPECT_LT((off - off.dot(k.axis) * k.axis).norm(), 1e-10);
      // Its projection is the foot of the mouse on the projected axis (two far axis points).
      const Eigen::Vector2d a = px(view, c0 - 0.5 * k.axis), b = px(view, c0 + 0.5 * k.axis);
      const Eigen::Vector2d u = (b - a).normalized();
      const Eigen::Vector2d foot = a + (mouse - a).dot(u) * u;
      EXPECT_LT((px(view, c) - foot).norm(), 1e-6) << "axis " << axis << " presses " << k.presses;
    }
  }
}

TEST(ModalTransform, AxisGrabFromOffCentreStartsAtZero) {
  const ScreenView view = perspective_view();
  const Manipulator start = rotated_start();
  const Eigen::Vector2d m0 = px(view, centre(start)) + Eigen::Vector2d(20, 40);
  ModalTransform t(TransformKind::Grab, start, kPivot, view, m0);
  t.press_axis(1);
  t.move_mouse(m0);
  EXPECT_LT((t.current().translation - start.translation).norm(), 1e-14);
  t.move_mouse(m0 + Eigen::Vector2d(30, 5));
  const Vec3 d = t.current().translation - start.translation;
  EXPECT_GT(d.norm(), 1e-3);
  EXPECT_EQ(d.x(), 0.0);
  EXPECT_EQ(d.z(), 0.0);
}

// Mouse positions sweeping counter-clockwise as seen (pixel y points down) around c.
Eigen::Vector2d on_circle(const Eigen::Vector2d& c, double r, double deg) {
  const double a = deg * kPi / 180.0;
  return c + r * Eigen::Vector2d(std::cos(a), -std::sin(a));
}

TEST(ModalTransform, RotateByMouseSweep) {
  const ScreenView view = perspective_view();
  const Manipulator start = rotated_start();
  const Vec3 c0 = centre(start);
  const Eigen::Vector2d c_px = px(view, c0);
  ModalTransform t(TransformKind::Rotate, start, kPivot, view, on_circle(c_px, 80, 20));
  for (double deg = 30; deg <= 110 + 1e-9; deg += 10) t.move_mouse(on_circle(c_px, 80 + deg, deg));
  const Manipulator m = t.current();
  const Eigen::Matrix3d rd = Eigen::AngleAxisd(kPi / 2, -view.forward()).toRotationMatrix();
  EXPECT_LT((rot(m) - rd * rot(start)).norm(), 1e-12);
  EXPECT_EQ(m.translation, start.translation);
  EXPECT_EQ(t.status(), "Rotate  view: 90.0\xC2\xB0");
  // As seen: a point to the right of the centre ends up above it.
  const Vec3 right = view.forward().cross(view.camera.up).normalized();
  const Vec3 x = start.to_affine(kPivot).inverse() * (c0 + 0.1 * right);
  const Eigen::Vector2d moved = px(view, apply(m, x)) - c_px;
  EXPECT_LT(moved.y(), -10.0);
  EXPECT_LT(std::abs(moved.x()), 0.2 * std::abs(moved.y()));
}

TEST(ModalTransform, RotateSweepAccumulatesTurns) {
  const ScreenView view = perspective_view();
  const Eigen::Vector2d c_px = px(view, centre(rotated_start()));
  ModalTransform t(TransformKind::Rotate, rotated_start(), kPivot, view, on_circle(c_px, 60, 0));
  for (double deg = -15; deg >= -450 - 1e-9; deg -= 15) t.move_mouse(on_circle(c_px, 60, deg));
  EXPECT_EQ(t.status(), "Rotate  view: -450.0\xC2\xB0");
}

TEST(ModalTransform, RotateLockedAxisFacingViewerKeepsScreenSense) {
  const ScreenView view = perspective_view();  // above the scene: +Z points towards the viewer
  ASSERT_GT(Vec3::UnitZ().dot(-view.forward()), 0.0);
  const Manipulator start = rotated_start();
  const Eigen::Vector2d c_px = px(view, centre(start));
  ModalTransform t(TransformKind::Rotate, start, kPivot, view, on_circle(c_px, 100, 0));
  t.press_axis(2);
  for (double deg = 10; deg <= 60 + 1e-9; deg += 10) t.move_mouse(on_circle(c_px, 100, deg));
  const Eigen::Matrix3d rz = Eigen::AngleAxisd(kPi / 3, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_LT((rot(t.current()) - rz * rot(start)).norm(), 1e-12);
  // Seen from below, +Z points away from the viewer: the same sweep is -60 degrees about +Z.
  ScreenView below = view;
  below.camera.eye.z() = -3.0;
  const Eigen::Vector2d cb = px(below, centre(start));
  ModalTransform u(TransformKind::Rotate, start, kPivot, below, on_circle(cb, 100, 0));
  u.press_axis(2);
  for (double deg = 10; deg <= 60 + 1e-9; deg += 10) u.move_mouse(on_circle(cb, 100, deg));
  EXPECT_LT((rot(u.current()) - rz.transpose() * rot(start)).norm(), 1e-12);
}

TEST(ModalTransform, ScaleByMouseDistance) {
  const ScreenView view = perspective_view();
  const Manipulator start = rotated_start();
  const Eigen::Vector2d c_px = px(view, centre(start));
  ModalTransform t(TransformKind::Scale, start, kPivot, view, c_px + Eigen::Vector2d(40, 30));
  t.move_mouse(c_px + Eigen::Vector2d(-80, 60));  // twice as far
  EXPECT_LT((t.current().scale - 2.0 * start.scale).norm(), 1e-12);
  EXPECT_EQ(t.current().translation, start.translation);
  t.press_axis(0);
  const Vec3 s = t.current().scale;
  EXPECT_NEAR(s.x(), 2.0 * start.scale.x(), 1e-12);
  EXPECT_EQ(s.y(), start.scale.y());
  EXPECT_EQ(s.z(), start.scale.z());
  t.move_mouse(c_px + Eigen::Vector2d(10, 0));  // a fifth of the start distance
  EXPECT_NEAR(t.current().scale.x(), 0.2 * start.scale.x(), 1e-12);
  type(t, "0");  // a typed zero would be singular: clamped
  EXPECT_GT(std::abs(t.current().scale.x()), 0.0);
  EXPECT_NO_THROW(t.current().to_affine(kPivot));
}

TEST(ModalTransform, RejectsBadInput) {
  Manipulator zero;
  zero.rotation.coeffs().setZero();
  EXPECT_THROW(ModalTransform(TransformKind::Grab, zero, kPivot, perspective_view(), {1, 1}), InvalidInput);
  EXPECT_THROW(ModalTransform(TransformKind::Grab, Manipulator{}, Vec3(NAN, 0, 0), perspective_view(), {1, 1}),
               InvalidInput);
}

}  // namespace
}  // namespace freeform::editor
