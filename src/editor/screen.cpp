#include "editor/screen.h"

#include <cmath>
#include <numbers>

namespace freeform::editor {

Eigen::Matrix4d ScreenView::view_projection() const { return camera.projection(aspect()) * camera.view(); }

std::optional<Eigen::Vector3d> ScreenView::project(const Vec3& p) const {
  const Eigen::Vector4d c = view_projection() * p.homogeneous();
  if (!(c.w() > 0.0)) return std::nullopt;
  const Eigen::Vector3d ndc = c.head<3>() / c.w();
  return Eigen::Vector3d(0.5 * (ndc.x() + 1.0) * width, 0.5 * (1.0 - ndc.y()) * height, ndc.z());
}

Ray ScreenView::ray(const Eigen::Vector2d& pixel) const {
  const double ndc_x = 2.0 * pixel.x() / width - 1.0;
  const double ndc_y = 1.0 - 2.0 * pixel.y() / height;
  const Eigen::Matrix4d inv = view_projection().inverse();
  Eigen::Vector4d a = inv * Eigen::Vector4d(ndc_x, ndc_y, -1.0, 1.0);
  Eigen::Vector4d b = inv * Eigen::Vector4d(ndc_x, ndc_y, 1.0, 1.0);
  const Vec3 pa = a.head<3>() / a.w(), pb = b.head<3>() / b.w();
  return {camera.eye, (pb - pa).normalized()};
}

Vec3 ScreenView::forward() const { return (camera.target - camera.eye).normalized(); }

double ScreenView::world_per_pixel(const Vec3& p) const {
  const double depth = std::max((p - camera.eye).dot(forward()), 1e-12);
  const double half_height = depth * std::tan(0.5 * camera.fov_y_deg * std::numbers::pi / 180.0);
  return 2.0 * half_height / height;
}

}  // namespace freeform::editor
