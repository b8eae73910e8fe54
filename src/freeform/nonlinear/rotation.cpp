#include "freeform/nonlinear/rotation.h"

#include <Eigen/Cholesky>

#include <cmath>

namespace freeform {
namespace {
constexpr double kQuadraticExit = 1e-7;
}  // namespace

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

int extract_rotation(const Eigen::Matrix3d& a, Eigen::Quaterniond& q, int max_iterations) {
  for (int it = 0; it < max_iterations; ++it) {
    // f(R exp([d])) = tr((R exp([d]))^T a) ~ f + g.d - d^T H d / 2 with S = R^T a,
    // g = vee(S - S^T), H = tr(S) I - sym(S): positive definite near the maximum.
    const Eigen::Matrix3d s = q.toRotationMatrix().transpose() * a;
    const Vec3 g(s(2, 1) - s(1, 2), s(0, 2) - s(2, 0), s(1, 0) - s(0, 1));
    const double tr = s.trace();
    const Eigen::Matrix3d h = tr * Eigen::Matrix3d::Identity() - 0.5 * (s + s.transpose());
    const Eigen::LLT<Eigen::Matrix3d> llt(h);
    const double floor = 1e-9 * std::abs(tr);
    const bool newton = tr > 0 && llt.info() == Eigen::Success && llt.matrixLLT().diagonal().minCoeff() > std::sqrt(floor);
    // Newton's step where H is safely definite (quadratic convergence); elsewhere Mueller
    // et al.'s gradient step, which turns towards the maximum from any start.
    Vec3 d = newton ? Vec3(llt.solve(g)) : Vec3(g / (std::abs(tr) + 1e-300));
    const double angle = d.norm();
    if (!(angle > 1e-13)) return it;  // also stops on NaN: q stays a rotation
    if (angle > 1.0) d *= 1.0 / angle;  // far from the maximum the model is not trusted
    const Eigen::Quaterniond step = angle < 1e-4 ? Eigen::Quaterniond(1.0, 0.5 * d.x(), 0.5 * d.y(), 0.5 * d.z())
                                                 : rotation_from_vector(d);
    q = (q * step).normalized();
    // Newton converges quadratically: after a step this small the next one would be below the
    // stopping threshold, so confirming it costs a whole iteration for nothing.
    if (newton && angle < kQuadraticExit) return it + 1;
  }
  return max_iterations;
}

}  // namespace freeform
