#include "editor/camera_controller.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace freeform::editor {
namespace {

constexpr double kPoleMargin = 0.01;  // radians kept between the view direction and the up axis

// A unit vector perpendicular to a (unit).
Eigen::Vector3d any_perpendicular(const Eigen::Vector3d& a) {
  const Eigen::Vector3d t = std::abs(a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return a.cross(t).normalized();
}

double tan_half_fov(const viewer::Camera& c) { return std::tan(0.5 * c.fov_y_deg * std::numbers::pi / 180.0); }

}  // namespace

void CameraController::set_camera(const viewer::Camera& camera) {
  camera_ = camera;
  if (camera.up.norm() > 0.0) up_axis_ = camera.up.normalized();
  refit_clip_planes();
}

void CameraController::set_up_axis(const Eigen::Vector3d& axis) {
  if (!(axis.norm() > 0.0)) throw InvalidInput("camera up axis must not be the zero vector");
  up_axis_ = axis.normalized();
  camera_.up = up_axis_;
}

void CameraController::set_bounds(const viewer::BoundingBox& box) {
  bounds_ = box;
  refit_clip_planes();
}

double CameraController::min_distance() const { return 1e-3 * std::max(bounds_.radius(), 1e-9); }

void CameraController::orbit(double dx_pixels, double dy_pixels) {
  const Eigen::Vector3d offset = camera_.eye - camera_.target;
  const double d = offset.norm();
  if (!(d > 0.0)) return;
  const Eigen::Vector3d& a = up_axis_;
  // offset = d (cos(theta) a + sin(theta) h), h horizontal; theta = 0 looks straight down.
  const double theta = std::acos(std::clamp(offset.dot(a) / d, -1.0, 1.0));
  Eigen::Vector3d h = offset - offset.dot(a) * a;
  if (h.norm() < 1e-9 * d) {
    // On a pole: the horizontal direction the screen's up vector points away from.
    const Eigen::Vector3d u = camera_.up - camera_.up.dot(a) * a;
    h = u.norm() > 1e-9 ? Eigen::Vector3d(-u.normalized() * (offset.dot(a) > 0 ? 1.0 : -1.0)) : any_perpendicular(a);
  }
  h.normalize();
  // Dragging down lifts the eye (the object's top comes into view); dragging right turns the
  // object to the right, i.e. the eye to the left.
  const double new_theta = std::clamp(theta - dy_pixels * kOrbitRadiansPerPixel, kPoleMargin, std::numbers::pi - kPoleMargin);
  const double yaw = -dx_pixels * kOrbitRadiansPerPixel;
  const Eigen::Vector3d h2 = std::cos(yaw) * h + std::sin(yaw) * a.cross(h);
  camera_.eye = camera_.target + d * (std::cos(new_theta) * a + std::sin(new_theta) * h2);
  camera_.up = a;
  refit_clip_planes();
}

void CameraController::pan(double dx_pixels, double dy_pixels, int viewport_height) {
  const double d = distance();
  if (!(d > 0.0) || viewport_height <= 0) return;
  const Eigen::Matrix4d v = camera_.view();
  const Eigen::Vector3d right = v.block<1, 3>(0, 0).transpose(), screen_up = v.block<1, 3>(1, 0).transpose();
  const double world_per_pixel = 2.0 * d * tan_half_fov(camera_) / viewport_height;
  // The scene follows the cursor, so the camera moves the other way (pixel y points down).
  const Eigen::Vector3d delta = world_per_pixel * (-dx_pixels * right + dy_pixels * screen_up);
  camera_.eye += delta;
  camera_.target += delta;
  refit_clip_planes();
}

void CameraController::zoom(double factor) {
  if (!(factor > 0.0) || !std::isfinite(factor)) return;
  const double d = distance();
  if (!(d > 0.0)) return;
  const double new_d = std::max(d * factor, std::min(min_distance(), d));
  camera_.eye = camera_.target + (new_d / d) * (camera_.eye - camera_.target);
  refit_clip_planes();
}

void CameraController::wheel(double steps) { zoom(std::pow(kWheelFactor, steps)); }

void CameraController::fit(const viewer::BoundingBox& box, double aspect, double margin) {
  Eigen::Vector3d dir = camera_.eye - camera_.target;  // from the target towards the eye
  dir = dir.norm() > 0.0 ? Eigen::Vector3d(dir.normalized()) : Eigen::Vector3d(0, -1, 0);
  Eigen::Vector3d s = (-dir).cross(camera_.up);
  if (s.norm() < 1e-9) s = any_perpendicular(dir);
  s.normalize();
  const Eigen::Vector3d u = s.cross(-dir);
  const double tan_y = tan_half_fov(camera_), tan_x = tan_y * aspect;
  // A corner at offset o from the centre lies at depth D - o.dir and must satisfy
  // |o.s| <= tan_x (D - o.dir) / margin and |o.u| <= tan_y (D - o.dir) / margin.
  double distance = 0.0;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d p(i & 1 ? box.max.x() : box.min.x(), i & 2 ? box.max.y() : box.min.y(),
                            i & 4 ? box.max.z() : box.min.z());
    const Eigen::Vector3d o = p - box.center();
    distance = std::max({distance, o.dot(dir) + margin * std::abs(o.dot(s)) / tan_x,
                         o.dot(dir) + margin * std::abs(o.dot(u)) / tan_y});
  }
  distance = std::max(distance, 1e-6 * std::max(1.0, box.center().norm()));
  camera_.target = box.center();
  camera_.eye = camera_.target + distance * dir;
  bounds_ = box;
  refit_clip_planes();
}

void CameraController::reset(const viewer::BoundingBox& box, viewer::ViewPreset preset, viewer::UpAxis up, double aspect) {
  up_axis_ = up == viewer::UpAxis::Z ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitY();
  camera_.target = box.center();
  camera_.eye = camera_.target + viewer::preset_direction(preset, up);
  camera_.up = viewer::preset_up(preset, up);
  fit(box, aspect);
}

void CameraController::refit_clip_planes() {
  camera_.fit_clip_planes(bounds_);
}

}  // namespace freeform::editor
