#include "freeform/nonlinear/rotation.h"

#include <cmath>

namespace freeform {

Vec3 rotation_vector(const Eigen::Quaterniond& q) {
  Eigen::Quaterniond u = q.normalized();
  if (u.w() < 0) u.coeffs() *= -1.0;  // the short way round
  const double s = u.vec().norm();
  if (s < 1e-300) return Vec3::Zero();
  return (2.0 * std::atan2(s, u.w()) / s) * u.vec();
}

Eigen::Quaterniond rotation_from_vector(const Vec3& w) {
  const double angle = w.norm();
  if (angle < 1e-300) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w / angle));
}

void extract_rotation(const Eigen::Matrix3d& a, Eigen::Quaterniond& q, int max_iterations) {
  for (int it = 0; it < max_iterations; ++it) {
    const Eigen::Matrix3d r = q.toRotationMatrix();
    const Vec3 torque = r.col(0).cross(a.col(0)) + r.col(1).cross(a.col(1)) + r.col(2).cross(a.col(2));
    const double denom = std::abs(r.col(0).dot(a.col(0)) + r.col(1).dot(a.col(1)) + r.col(2).dot(a.col(2))) + 1e-300;
    const Vec3 omega = torque / denom;
    const double angle = omega.norm();
    if (!(angle > 1e-12)) break;  // also stops on NaN: q stays a rotation
    q = (Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega / angle)) * q).normalized();
  }
}

}  // namespace freeform
