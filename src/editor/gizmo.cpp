#include "editor/gizmo.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace freeform::editor {

namespace {

constexpr double kHeadLength = kGizmoHeadLength, kHeadHalfWidth = kGizmoHeadHalfWidth, kRingRadius = kGizmoRingRadius,
                 kBoxAt = kGizmoBoxAt, kBoxHalf = kGizmoBoxHalf, kCenterRadius = kGizmoCenterRadius;
constexpr double kMinArmPx = kGizmoMinArmPx;
constexpr int kRingSegments = 64;

GizmoPart part_of(GizmoPart first, int axis) { return static_cast<GizmoPart>(static_cast<int>(first) + axis); }

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

double polyline_distance(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& pts) {
  double best = std::numeric_limits<double>::infinity();
  if (pts.size() == 1) return (p - pts[0]).norm();
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) best = std::min(best, segment_distance(p, pts[i], pts[i + 1]));
  return best;
}

double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

double triangle_distance(const Eigen::Vector2d& p, const std::array<Eigen::Vector2d, 3>& t) {
  const double d0 = cross2(t[1] - t[0], p - t[0]), d1 = cross2(t[2] - t[1], p - t[1]),
               d2 = cross2(t[0] - t[2], p - t[2]);
  const bool inside = (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
  if (inside) return 0.0;
  return std::min({segment_distance(p, t[0], t[1]), segment_distance(p, t[1], t[2]), segment_distance(p, t[2], t[0])});
}

double box_distance(const Eigen::Vector2d& p, const GizmoBox& b) {
  const Eigen::Vector2d d = ((p - b.center).cwiseAbs().array() - b.half_size).max(0.0).matrix();
  return d.norm();
}

std::optional<Eigen::Vector2d> project2(const ScreenView& view, const Vec3& p) {
  const auto q = view.project(p);
  if (!q) return std::nullopt;
  return q->head<2>();
}

// The ring about `axis` (unit) of world radius r, split into runs of front / back segments.
void add_ring(GizmoShape& shape, const ScreenView& view, const Vec3& c, const Vec3& axis, double r, GizmoPart part,
              GizmoColor color, float back_alpha) {
  const Vec3 u = axis.unitOrthogonal(), v = axis.cross(u);
  const Vec3 to_eye = view.camera.eye - c;
  GizmoPolyline run;
  auto flush = [&] {
    if (run.points.size() >= 2) shape.rings.push_back(run);
    run.points.clear();
  };
  // (No std::optional here: GCC 12 -O3 flags an Eigen vector inside one as maybe-uninitialized.)
  Eigen::Vector2d prev = Eigen::Vector2d::Zero();
  bool has_prev = false, prev_front = true;
  for (int k = 0; k <= kRingSegments; ++k) {
    const double phi = 2.0 * std::numbers::pi * k / kRingSegments;
    const Vec3 offset = r * (std::cos(phi) * u + std::sin(phi) * v);
    const auto q = project2(view, c + offset);
    const bool front = offset.dot(to_eye) >= 0.0;
    if (!q) {  // behind the eye: break the ring
      flush();
      has_prev = false;
      continue;
    }
    if (has_prev && front != prev_front) {  // start a new run at the previous point
      flush();
      run.points.push_back(prev);
    }
    run.part = part;
    run.front = front;
    run.color = color;
    if (!front) run.color.a *= back_alpha;
    run.thickness = front ? 2.0f : 1.5f;
    run.points.push_back(*q);
    prev = *q;
    has_prev = true;
    prev_front = front;
  }
  flush();
}

}  // namespace

GizmoShape gizmo_shape(const ScreenView& view, const Vec3& center, const Eigen::Quaterniond& local, double arm_px,
                       GizmoPart hovered, const GizmoPalette& palette) {
  if (!center.allFinite() || !local.coeffs().allFinite() || !std::isfinite(arm_px))
    throw InvalidInput("gizmo: centre, rotation and arm length must be finite");
  if (!(local.norm() > 1e-12)) throw InvalidInput("gizmo: the handle rotation is a zero quaternion");
  if (!(arm_px > 0.0)) throw InvalidInput("gizmo: the arm length must be a positive number of pixels");
  GizmoShape shape;
  const auto c2 = project2(view, center);
  if (!c2) return shape;
  shape.visible = true;
  shape.center = *c2;
  shape.center_radius = kCenterRadius * arm_px;
  shape.center_color = hovered == GizmoPart::Center ? palette.hovered : palette.center;
  const double arm = arm_px * view.world_per_pixel(center);  // world length of an arm
  auto color = [&](GizmoPart part, int axis) { return part == hovered ? palette.hovered : palette.axis[axis]; };

  for (int i = 0; i < 3; ++i) {
    const GizmoPart rot = part_of(GizmoPart::RotateX, i);
    add_ring(shape, view, center, Vec3::Unit(i), kRingRadius * arm, rot, color(rot, i), palette.back_alpha);
  }
  // Back ring pieces first so the front ones are drawn over them.
  std::stable_partition(shape.rings.begin(), shape.rings.end(), [](const GizmoPolyline& p) { return !p.front; });

  const Eigen::Matrix3d axes = local.normalized().toRotationMatrix();
  for (int i = 0; i < 3; ++i) {
    const GizmoPart move = part_of(GizmoPart::MoveX, i);
    if (const auto tip = project2(view, center + arm * Vec3::Unit(i))) {
      const Eigen::Vector2d d = *tip - *c2;
      const double len = d.norm();
      if (len >= kMinArmPx) {
        const Eigen::Vector2d dir = d / len, side(-dir.y(), dir.x());
        const Eigen::Vector2d base = *tip - std::min(kHeadLength * arm_px, 0.5 * len) * dir;
        const Eigen::Vector2d start = *c2 + std::min(shape.center_radius, 0.5 * len) * dir;
        const double w = kHeadHalfWidth * arm_px;
        shape.arms.push_back({move, {start, base}, color(move, i), 2.0f, true});
        shape.arrowheads.push_back({move, {*tip, base + w * side, base - w * side}, color(move, i)});
      }
    }
    const GizmoPart scale = part_of(GizmoPart::ScaleX, i);
    const Vec3 a = axes.col(i);
    const auto end = project2(view, center + arm * a), at = project2(view, center + kBoxAt * arm * a);
    if (end && at && (*end - *c2).norm() >= kMinArmPx)
      shape.boxes.push_back({scale, *at, kBoxHalf * arm_px, color(scale, i)});
  }
  return shape;
}

GizmoPart gizmo_hit(const GizmoShape& shape, const Eigen::Vector2d& mouse, double tolerance_px) {
  if (!shape.visible) return GizmoPart::None;
  if ((mouse - shape.center).norm() <= shape.center_radius + tolerance_px) return GizmoPart::Center;
  GizmoPart best = GizmoPart::None;
  double best_d = std::numeric_limits<double>::infinity();
  auto consider = [&](GizmoPart part, double d) {
    if (d <= tolerance_px && d < best_d) best = part, best_d = d;
  };
  for (const auto& t : shape.arrowheads) consider(t.part, triangle_distance(mouse, t.corners));
  for (const auto& b : shape.boxes) consider(b.part, box_distance(mouse, b));
  if (best != GizmoPart::None) return best;
  for (const auto& r : shape.rings) consider(r.part, polyline_distance(mouse, r.points));
  if (best != GizmoPart::None) return best;
  for (const auto& a : shape.arms) consider(a.part, polyline_distance(mouse, a.points));
  return best;
}

TransformKind gizmo_kind(GizmoPart part) {
  switch (part) {
    case GizmoPart::Center:
    case GizmoPart::MoveX:
    case GizmoPart::MoveY:
    case GizmoPart::MoveZ:
      return TransformKind::Grab;
    case GizmoPart::RotateX:
    case GizmoPart::RotateY:
    case GizmoPart::RotateZ:
      return TransformKind::Rotate;
    case GizmoPart::ScaleX:
    case GizmoPart::ScaleY:
    case GizmoPart::ScaleZ:
      return TransformKind::Scale;
    case GizmoPart::None:
      break;
  }
  throw InvalidInput("gizmo: no part under the mouse; start a gizmo drag only on a hit part");
}

AxisLock gizmo_axis(GizmoPart part) {
  switch (part) {
    case GizmoPart::MoveX:
    case GizmoPart::RotateX:
      return AxisLock::GlobalX;
    case GizmoPart::MoveY:
    case GizmoPart::RotateY:
      return AxisLock::GlobalY;
    case GizmoPart::MoveZ:
    case GizmoPart::RotateZ:
      return AxisLock::GlobalZ;
    case GizmoPart::ScaleX:
      return AxisLock::LocalX;
    case GizmoPart::ScaleY:
      return AxisLock::LocalY;
    case GizmoPart::ScaleZ:
      return AxisLock::LocalZ;
    case GizmoPart::None:
    case GizmoPart::Center:
      break;
  }
  return AxisLock::None;
}

GizmoDrag::GizmoDrag(GizmoPart part, const Manipulator& start, const Vec3& pivot, const ScreenView& view,
                     const Eigen::Vector2d& mouse)
    : part_(part), transform_(gizmo_kind(part), start, pivot, view, mouse) {
  transform_.set_axis(gizmo_axis(part));
}

}  // namespace freeform::editor
