// The 9-dof manipulator (edit/manipulator.h): x' = pivot + R S (x - pivot) + t against hand-computed
// images, its default pivot, and the refusals (zero axis, zero or NaN scale, a projective or
// singular 4x4 matrix).
#include "freeform/common/error.h"
#include "freeform/edit/manipulator.h"

#include <gtest/gtest.h>

#include <cmath>

namespace freeform {
namespace {

TEST(Manipulator, ToAffineAndChecks) {
  Manipulator m;
  m.translation = Vec3(1, 2, 3);
  m.rotation = Manipulator::axis_angle(Vec3(0, 0, 2), 90.0);
  m.scale = Vec3(2, 1, 1);
  const Vec3 pivot(1, 0, 0);
  const Eigen::Affine3d t = m.to_affine(pivot);
  // x -> pivot + R S (x - pivot) + t: (2,0,0) -> (1,0,0) + R (2,0,0) + t = (1,2,0) + t
  EXPECT_LT((t * Vec3(2, 0, 0) - Vec3(2, 4, 3)).norm(), 1e-14);
  EXPECT_LT((t * pivot - (pivot + m.translation)).norm(), 1e-14);
  m.pivot = Vec3::Zero();
  EXPECT_LT((m.to_affine(pivot) * Vec3::Zero() - m.translation).norm(), 1e-14);
  EXPECT_THROW(Manipulator::axis_angle(Vec3::Zero(), 10), InvalidInput);
  Manipulator bad;
  bad.scale = Vec3(1, 0, 1);
  EXPECT_THROW(bad.to_affine(pivot), InvalidInput);
  bad.scale = Vec3(1, std::nan(""), 1);
  EXPECT_THROW(bad.to_affine(pivot), InvalidInput);

  Eigen::Matrix4d mat = Eigen::Matrix4d::Identity();
  mat(0, 3) = 5;
  EXPECT_LT((affine_from_matrix(mat) * Vec3::Zero() - Vec3(5, 0, 0)).norm(), 1e-15);
  mat(3, 0) = 1;
  EXPECT_THROW(affine_from_matrix(mat), InvalidInput);
  mat(3, 0) = 0;
  mat(2, 2) = 0;
  EXPECT_THROW(affine_from_matrix(mat), InvalidInput);
  mat(2, 2) = std::nan("");
  EXPECT_THROW(affine_from_matrix(mat), InvalidInput);
}

}  // namespace
}  // namespace freeform
