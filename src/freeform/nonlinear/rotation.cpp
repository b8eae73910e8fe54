#include "freeform/nonlinear/rotation.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
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
    // H's LDL^T written out: cheaper than a general 3 x 3 Cholesky.
    const double h00 = tr - s(0, 0), h11 = tr - s(1, 1), h22 = tr - s(2, 2);
    const double h01 = -0.5 * (s(0, 1) + s(1, 0)), h02 = -0.5 * (s(0, 2) + s(2, 0)), h12 = -0.5 * (s(1, 2) + s(2, 1));
    const double floor = 1e-9 * std::abs(tr);
    // Newton's step where H is safely definite (quadratic convergence); elsewhere Mueller
    // et al.'s gradient step, which turns towards the maximum from any start.
    bool newton = false;
    Vec3 d = g / (std::abs(tr) + 1e-300);
    if (tr > 0 && h00 > floor) {
      const double l10 = h01 / h00, l20 = h02 / h00, p1 = h11 - l10 * h01;
      if (p1 > floor) {
        const double r12 = h12 - l20 * h01, l21 = r12 / p1, p2 = h22 - l20 * h02 - l21 * r12;
        newton = p2 > floor;
        if (newton) {
          const double y1 = g(1) - l10 * g(0), y2 = g(2) - l20 * g(0) - l21 * y1;
          d(2) = y2 / p2;
          d(1) = y1 / p1 - l21 * d(2);
          d(0) = g(0) / h00 - l10 * d(1) - l20 * d(2);
        }
      }
    }
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

double fit_conditioning(const Eigen::Matrix3d& a, const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d s = q.toRotationMatrix().transpose() * a;
  const Eigen::Matrix3d h = s.trace() * Eigen::Matrix3d::Identity() - 0.5 * (s + s.transpose());
  const double trace = h.trace();
  if (!(trace > 0.0)) return 0.0;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(h, Eigen::EigenvaluesOnly);  // closed form, ascending
  return std::clamp(eigen.eigenvalues()(0) / trace, 0.0, 1.0 / 3.0);
}

}  // namespace freeform
