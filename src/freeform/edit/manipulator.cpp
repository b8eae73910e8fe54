// 9-dof manipulators and checked affine maps (docs/bcm.md).
#include "freeform/edit/manipulator.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"

#include <cmath>
#include <numbers>

namespace freeform {

Eigen::Quaterniond Manipulator::axis_angle(const Vec3& axis, double degrees) {
  if (!axis.allFinite() || !std::isfinite(degrees))
    throw InvalidInput("rotation axis and angle must be finite numbers");
  // Scaled by its largest component first: axis.norm() overflows above ~1e154 (the rotation
  // silently became the identity) and underflows below ~1e-154 ("zero vector").
  const double m = axis.cwiseAbs().maxCoeff();
  if (!(m > 0.0)) throw InvalidInput("rotation axis is the zero vector; give a direction such as (0, 0, 1)");
  return Eigen::Quaterniond(Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, (axis / m).normalized()));
}

Eigen::Affine3d Manipulator::to_affine(const Vec3& default_pivot) const {
  const Vec3 p = pivot.value_or(default_pivot);
  if (!translation.allFinite() || !rotation.coeffs().allFinite() || !scale.allFinite() || !p.allFinite())
    throw InvalidInput("manipulator has a non-finite translation, rotation, scale or pivot");
  const double qn = rotation.norm();
  if (!(qn > 1e-12)) throw InvalidInput("manipulator rotation is a zero quaternion; use the identity (1, 0, 0, 0)");
  if (!(scale.cwiseAbs().minCoeff() > kMinScale))
    throw InvalidInput(scale.cwiseAbs().minCoeff() == 0.0
                           ? std::string("manipulator scale has a zero component; the transform would be singular")
                           : "manipulator scale has a component of " + json_messages::num(scale.cwiseAbs().minCoeff()) +
                                 ", at most 1e-12 in size; the transform would be numerically singular");
  const Eigen::Matrix3d rs = (Eigen::Quaterniond(rotation.coeffs() / qn).toRotationMatrix()) * scale.asDiagonal();
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.linear() = rs;
  t.translation() = p + translation - rs * p;
  return t;
}

bool is_identity(const Manipulator& m) {
  return m.translation == Vec3::Zero() && m.scale == Vec3::Ones() &&
         m.rotation.coeffs() == Eigen::Quaterniond::Identity().coeffs();
}

Eigen::Affine3d affine_from_matrix(const Eigen::Matrix4d& m) {
  if (!m.allFinite()) throw InvalidInput("transform matrix has non-finite entries");
  const Eigen::RowVector4d last = m.row(3);
  if ((last - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-12)
    throw InvalidInput("transform matrix is not affine: its last row must be (0 0 0 1)");
  const Eigen::Matrix3d lin = m.topLeftCorner<3, 3>();
  const double scale = lin.colwise().norm().maxCoeff();
  const double det = lin.determinant();
  if (!(scale > 0.0) || !(std::abs(det) > 1e-12 * scale * scale * scale))
    throw InvalidInput("transform matrix is singular (its 3x3 linear part is not invertible)");
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.matrix() = m;
  t.matrix().row(3) << 0, 0, 0, 1;
  return t;
}

}  // namespace freeform
