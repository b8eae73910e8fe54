// The on-screen manipulator gizmo of the selected handle (GL-free): move arrows and rotate
// rings about the world axes, scale boxes on the handle's local axes and a free-drag centre.
// gizmo_shape() gives 2D primitives in pixels (x right, y down; see screen.h) for the app to
// draw with ImGui's draw list, gizmo_hit() picks a part under the mouse, and GizmoDrag turns a
// drag on a part into the ModalTransform semantics (modal_transform.h).
//
// Sizes are screen-constant, in pixels for arm_px = 100 (they scale with arm_px): arrow tips
// at the arm length, arrowheads 16 long and 12 wide, rings of radius 0.7 * arm (3D circles,
// projected), scale boxes 10 wide at 0.55 * arm along the local axes, centre circle radius 8.
// An axis whose arm projects shorter than 10 px (it points at the eye) gets no arm, arrowhead
// or scale box, so it cannot steal clicks.
#pragma once

#include "editor/modal_transform.h"
#include "editor/screen.h"

#include "freeform/edit/manipulator.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <vector>

namespace freeform::editor {

// Layout, as fractions of the arm (ring radius, box position along the arm) or of arm_px.
inline constexpr double kGizmoRingRadius = 0.7, kGizmoBoxAt = 0.55;
inline constexpr double kGizmoHeadLength = 0.16, kGizmoHeadHalfWidth = 0.06, kGizmoBoxHalf = 0.05,
                        kGizmoCenterRadius = 0.08;
inline constexpr double kGizmoMinArmPx = 10.0;  // shorter projected arms point at the eye

enum class GizmoPart { None, Center, MoveX, MoveY, MoveZ, RotateX, RotateY, RotateZ, ScaleX, ScaleY, ScaleZ };

struct GizmoColor {
  float r = 1, g = 1, b = 1, a = 1;  // linear 0..1
};

// X red, Y green, Z blue, centre white; the hovered part is drawn yellow; the back half of a
// ring has alpha 0.35.
struct GizmoPalette {
  GizmoColor axis[3] = {{0.90f, 0.25f, 0.25f, 1}, {0.35f, 0.80f, 0.30f, 1}, {0.25f, 0.45f, 0.95f, 1}};
  GizmoColor center{1, 1, 1, 1};
  GizmoColor hovered{1.0f, 0.85f, 0.25f, 1};
  float back_alpha = 0.35f;
};

struct GizmoPolyline {
  GizmoPart part = GizmoPart::None;
  std::vector<Eigen::Vector2d> points;  // open polyline
  GizmoColor color;
  float thickness = 2.0f;  // pixels
  bool front = true;       // rings: the half nearer the eye (draw the others dimmer, first)
};

struct GizmoTriangle {
  GizmoPart part = GizmoPart::None;
  std::array<Eigen::Vector2d, 3> corners;
  GizmoColor color;
};

struct GizmoBox {  // a filled square aligned with the screen
  GizmoPart part = GizmoPart::None;
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double half_size = 5.0;
  GizmoColor color;
};

// Draw in member order: rings (back pieces first), arms, arrowheads, boxes, centre circle.
struct GizmoShape {
  bool visible = false;  // false when the centre is behind the eye: nothing to draw or hit
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  double center_radius = 8.0;
  GizmoColor center_color;
  std::vector<GizmoPolyline> rings;  // pieces of the rotate rings, back pieces first
  std::vector<GizmoPolyline> arms;   // move arm lines
  std::vector<GizmoTriangle> arrowheads;
  std::vector<GizmoBox> boxes;
};

// The gizmo at `center` (the handle's current centre, pivot + t), scale boxes along the
// columns of `local` (the handle's rotation). Throws InvalidInput for non-finite input, a zero
// quaternion or arm_px <= 0.
GizmoShape gizmo_shape(const ScreenView& view, const Vec3& center,
                       const Eigen::Quaterniond& local = Eigen::Quaterniond::Identity(), double arm_px = 100.0,
                       GizmoPart hovered = GizmoPart::None, const GizmoPalette& palette = {});

// The part under the mouse (None if nothing within tolerance_px). Priority: centre, then
// arrowheads and boxes, then rings, then arm lines; within a tier the nearest wins.
GizmoPart gizmo_hit(const GizmoShape& shape, const Eigen::Vector2d& mouse, double tolerance_px = 6.0);

// What a drag on a part does: Center = free grab, MoveI = grab locked to global axis I,
// RotateI = rotate about global axis I, ScaleI = scale along the handle's local axis I.
TransformKind gizmo_kind(GizmoPart part);  // throws InvalidInput for None
AxisLock gizmo_axis(GizmoPart part);

// A drag started on a gizmo part: the same maths as the keyboard tools (modal_transform.h).
class GizmoDrag {
 public:
  // `pivot` is the resolved pivot of `start`; `mouse` where the button went down.
  // Throws InvalidInput for GizmoPart::None (and what ModalTransform throws).
  GizmoDrag(GizmoPart part, const Manipulator& start, const Vec3& pivot, const ScreenView& view,
            const Eigen::Vector2d& mouse);

  void move_mouse(const Eigen::Vector2d& mouse) { transform_.move_mouse(mouse); }
  Manipulator current() const { return transform_.current(); }
  const Manipulator& cancel() const { return transform_.cancel(); }
  GizmoPart part() const { return part_; }
  const ModalTransform& transform() const { return transform_; }  // e.g. for status()

 private:
  GizmoPart part_;
  ModalTransform transform_;
};

}  // namespace freeform::editor
