// The editor's camera navigation (GL-free): turntable orbit around the target, pan in the view
// plane, zoom towards the target and fitting the view to a bounding box, on a viewer::Camera.
// Inputs are pixel deltas in the screen convention of screen.h (x right, y down); the window
// code only translates mouse events into these calls. After every move the clip planes are
// refitted to the scene bounds given by set_bounds().
#pragma once

#include "viewer/camera.h"

#include <Eigen/Core>

namespace freeform::editor {

class CameraController {
 public:
  // Radians of orbit per pixel of mouse motion.
  static constexpr double kOrbitRadiansPerPixel = 0.008;
  // Distance factor per wheel step (one notch forward brings the eye closer).
  static constexpr double kWheelFactor = 0.88;

  CameraController() = default;
  explicit CameraController(const viewer::Camera& camera) : camera_(camera) {}

  const viewer::Camera& camera() const { return camera_; }
  void set_camera(const viewer::Camera& camera);

  // The world axis the turntable keeps upright (the camera's up vector after fit/reset).
  const Eigen::Vector3d& up_axis() const { return up_axis_; }
  void set_up_axis(const Eigen::Vector3d& axis);  // unit or not; must not be zero

  // Scene bounds used for the clip planes and the smallest zoom distance. Does not move the eye.
  void set_bounds(const viewer::BoundingBox& box);
  const viewer::BoundingBox& bounds() const { return bounds_; }

  // Turntable orbit by a mouse motion of (dx, dy) pixels: yaw around the up axis through the
  // target, pitch around the camera's right axis (clamped short of the poles). The distance
  // eye-target does not change.
  void orbit(double dx_pixels, double dy_pixels);
  // Moves eye and target by the same vector so that the point at the target's depth follows
  // the cursor: (dx, dy) pixels in a viewport `viewport_height` pixels high.
  void pan(double dx_pixels, double dy_pixels, int viewport_height);
  // Distance eye-target multiplied by `factor` (> 0; < 1 comes closer), kept at or above
  // min_distance(): the eye never reaches or passes the target. Non-positive factors are ignored.
  void zoom(double factor);
  // Mouse wheel: `steps` notches (positive: forward, closer).
  void wheel(double steps);
  double distance() const { return (camera_.eye - camera_.target).norm(); }
  double min_distance() const;

  // Keeps the view direction and up vector; moves the target to the box centre and the eye to
  // the smallest distance at which all eight corners are inside the view shrunk by 1/margin.
  void fit(const viewer::BoundingBox& box, double aspect, double margin = 1.08);
  // A preset view (viewer::fit_view) with the given up axis, which the turntable then keeps.
  void reset(const viewer::BoundingBox& box, viewer::ViewPreset preset, viewer::UpAxis up, double aspect);

 private:
  void refit_clip_planes();

  viewer::Camera camera_;
  Eigen::Vector3d up_axis_{0, 0, 1};
  viewer::BoundingBox bounds_{Eigen::Vector3d::Constant(-1.0), Eigen::Vector3d::Constant(1.0)};
};

}  // namespace freeform::editor
