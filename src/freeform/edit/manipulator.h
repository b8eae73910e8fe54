// The 9-dof manipulator of a handle (docs/bcm.md): x' = pivot + R S (x - pivot) + t.
// It is always applied to the original (rest) frame, never incrementally.
#pragma once

#include "freeform/mesh/types.h"

#include <Eigen/Geometry>

#include <optional>

namespace freeform {

struct Manipulator {
  static constexpr double kMinScale = 1e-12;  // smaller |scale| components make the map singular
  Vec3 translation = Vec3::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // normalized on use
  Vec3 scale = Vec3::Ones();                                     // per axis, in the pivot's frame
  std::optional<Vec3> pivot;                                     // default: the handle centroid

  // Rotation by `degrees` about `axis` (need not be unit; throws InvalidInput if zero).
  static Eigen::Quaterniond axis_angle(const Vec3& axis, double degrees);

  // The affine map x -> pivot + R S (x - pivot) + t, with `default_pivot` if pivot is unset.
  // Throws InvalidInput for non-finite values or a zero scale (singular transform).
  Eigen::Affine3d to_affine(const Vec3& default_pivot) const;
};

// No translation, rotation or scale (the pivot is ignored).
bool is_identity(const Manipulator& m);

// Throws InvalidInput unless the 4x4 matrix is finite, its last row is (0 0 0 1) and its
// linear part is invertible (|det| > 1e-12 * scale^3).
Eigen::Affine3d affine_from_matrix(const Eigen::Matrix4d& m);

}  // namespace freeform
