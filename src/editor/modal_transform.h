// Blender-style modal transform of a handle (GL-free): G / R / S start a grab / rotate / scale,
// X / Y / Z lock an axis, typed numbers set the amount, the app confirms or cancels.
//
// The handle's state is a Manipulator, x' = pivot + R S (x - pivot) + t, always applied to the
// rest handle; `pivot` is the resolved pivot (rest centroid unless the manipulator sets one).
// The handle's current centre is c0 = pivot + t0. Every result is computed from the start
// manipulator (R0, S0, t0) and the start mouse, never incrementally:
//
// Grab    t = t0 + d; R, S unchanged.
//         No lock: the centre follows the mouse in the plane through c0 parallel to the view
//         plane (d = hit(mouse) - hit(start mouse), hits of the mouse rays with that plane), so
//         the projected centre moves exactly with the mouse.
//         Axis lock: d = (s - s_start) a along the axis line c0 + s a. The mouse is first
//         snapped to the closest point of the projected axis, and s is where the ray through
//         that point meets the axis, so the centre stays under the cursor's foot on the axis
//         (this is the mouse ray/axis closest point, measured in pixels instead of world units).
//         Typed number: d = value * a (no lock: along global X, like Blender).
// Rotate  about the current centre: R = Rd R0, t unchanged (so the centre stays put).
//         The mouse angle is the signed angle swept around the centre's projection,
//         accumulated over move_mouse calls (several turns work), counter-clockwise as seen on
//         screen positive. No lock: the axis points from the centre towards the viewer (-forward),
//         so a counter-clockwise drag turns the handle counter-clockwise as seen. Axis lock: the
//         axis a is used with the sign flipped when a points away from the viewer (same
//         on-screen sense). Typed number: degrees about a (no lock: about -forward).
// Scale   about the current centre, factor f = |mouse - c_px| / |start mouse - c_px| (the
//         start distance is clamped to >= 1 px). No lock: S = f S0. Axis lock i: S = S0 with
//         component i multiplied by f, i.e. along the handle's LOCAL axis i: a global-axis
//         scale of a rotated handle is not a 9-dof manipulator, so for Scale global and local
//         locks are the same and the lock cycle is LocalI -> None. Typed number: the factor.
//         Factors with |f| < 1e-6 are clamped to +-1e-6 (the manipulator must stay regular).
//
// Axis keys cycle per key: X -> global X -> local X (column of R0) -> no lock; another axis
// key switches to that axis, global. Typed numbers: digits and '.', '-' toggles the sign,
// backspace deletes; while the digits parse as a number they override the mouse, otherwise
// (empty, "." ) the mouse drives the amount again. When the centre cannot be projected
// (behind the eye) the mouse has no effect; typed numbers still work.
#pragma once

#include "editor/screen.h"

#include "freeform/edit/manipulator.h"

#include <Eigen/Core>

#include <optional>
#include <string>

namespace freeform::editor {

enum class TransformKind { Grab, Rotate, Scale };
enum class AxisLock { None, GlobalX, GlobalY, GlobalZ, LocalX, LocalY, LocalZ };

// 0, 1, 2 for X, Y, Z locks; -1 for None.
int axis_index(AxisLock lock);
bool is_local(AxisLock lock);

class ModalTransform {
 public:
  // `pivot` is the resolved pivot of `start` (start.pivot if set, else the rest centroid);
  // `mouse` the cursor in pixels when the key was pressed. Throws InvalidInput for
  // non-finite input or a zero rotation quaternion.
  ModalTransform(TransformKind kind, const Manipulator& start, const Vec3& pivot, const ScreenView& view,
                 const Eigen::Vector2d& mouse);

  // Axis key (0 = X, 1 = Y, 2 = Z): cycles global -> local -> none (Scale: local -> none).
  // Throws InvalidInput for another index.
  void press_axis(int axis);
  // Sets the lock directly (used by the gizmo); Scale maps a global lock to the local one.
  void set_axis(AxisLock lock);
  // Digits, '.', '-' (toggles the sign). False if the character was not consumed (anything
  // else, a second '.', or a number longer than 32 characters).
  bool type_char(char c);
  void backspace();  // deletes the last digit; with no digits left, clears the sign
  void move_mouse(const Eigen::Vector2d& mouse);
  // A changed camera or viewport: the mouse amount is recomputed with the new view.
  void set_view(const ScreenView& view);

  Manipulator current() const;  // what to display now
  Manipulator confirm() const { return current(); }
  const Manipulator& cancel() const { return start_; }  // the caller restores it

  TransformKind kind() const { return kind_; }
  AxisLock axis() const { return lock_; }
  // Typed text ("-2.5", "" when none) and whether it overrides the mouse.
  const std::string& typed_text() const { return typed_text_; }
  bool typed_active() const { return typed_value().has_value(); }
  // For the status line, e.g. "Grab  X (global): 2.5", "Rotate  view: 37.2°",
  // "Scale  Y (local): 2".
  std::string status() const;

 private:
  std::optional<double> typed_value() const;
  Vec3 axis_vector() const;  // unit world direction of the lock (None: global X)
  void update_mouse_amount();
  void update_grab();
  double rotate_degrees() const;  // about axis_vector() / -forward, mouse or typed
  double scale_factor() const;

  TransformKind kind_;
  Manipulator start_;
  Vec3 pivot_;
  ScreenView view_;
  Eigen::Matrix3d r0_;  // start rotation
  Vec3 c0_;             // start centre, pivot + t0
  AxisLock lock_ = AxisLock::None;
  Eigen::Vector2d mouse_start_, mouse_;
  std::string typed_text_;  // optional '-' followed by digits and '.'
  // Mouse-driven amounts.
  Vec3 grab_ = Vec3::Zero();   // d
  double sweep_ = 0.0;         // accumulated counter-clockwise screen angle (radians)
  Eigen::Vector2d sweep_ref_;  // last mouse position away from the projected centre
};

}  // namespace freeform::editor
