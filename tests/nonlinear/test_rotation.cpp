// extract_rotation against the polar factor from Eigen's SVD (an independent method).
#include "freeform/nonlinear/rotation.h"

#include <Eigen/SVD>
#include <gtest/gtest.h>

#include <random>

namespace freeform {
namespace {

Eigen::Matrix3d polar_by_svd(const Eigen::Matrix3d& a) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0) u.col(2) *= -1.0;
  return u * svd.matrixV().transpose();
}

Eigen::Matrix3d random_rotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

// a = R diag(s) V^T with singular values s: a known polar factor R V^T.
struct Case {
  Eigen::Matrix3d a, polar;
};
Case make_case(std::mt19937& rng, const Vec3& s) {
  const Eigen::Matrix3d r = random_rotation(rng), v = random_rotation(rng);
  return {r * s.asDiagonal() * v.transpose(), r * v.transpose()};
}

TEST(Rotation, ExtractsThePolarFactorFromAnyStart) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.1, 3.0);
  int worst = 0;
  for (int i = 0; i < 2000; ++i) {
    const Case c = make_case(rng, Vec3(u(rng), u(rng), u(rng)));
    Eigen::Quaterniond q(random_rotation(rng));  // arbitrary start, up to 180 degrees off
    const int it = extract_rotation(c.a, q, 100);
    worst = std::max(worst, it);
    ASSERT_NEAR((q.toRotationMatrix() - c.polar).norm(), 0.0, 1e-9) << "case " << i;
    ASSERT_NEAR((q.toRotationMatrix() - polar_by_svd(c.a)).norm(), 0.0, 1e-9) << "case " << i;
  }
  EXPECT_LT(worst, 100);
}

TEST(Rotation, WarmStartsConvergeInAFewNewtonSteps) {
  // The nonlinear model's case: the last iteration's rotation, a little off; flat patches
  // (rank 2) and thin ones (s3 << s1) included, where gradient steps alone crawl.
  std::mt19937 rng(11);
  std::normal_distribution<double> n;
  for (const Vec3& s : {Vec3(1, 1, 1), Vec3(1, 0.8, 1e-3), Vec3(1, 1, 0), Vec3(2, 0.05, 0.01)}) {
    for (int i = 0; i < 200; ++i) {
      const Case c = make_case(rng, s);
      Eigen::Quaterniond q(c.polar);
      q = (q * Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Vec3(n(rng), n(rng), n(rng)).normalized()))).normalized();
      const int it = extract_rotation(c.a, q);
      EXPECT_LE(it, 5) << "singular values " << s.transpose();
      EXPECT_NEAR((q.toRotationMatrix() - c.polar).norm(), 0.0, 1e-10) << "singular values " << s.transpose();
    }
  }
}

TEST(Rotation, DegenerateMatricesGiveARotation) {
  // Rank 1 (collinear edges), zero and non-finite: no NaN, q stays a unit quaternion.
  std::mt19937 rng(3);
  const Eigen::Matrix3d rank1 = Vec3(1, 2, 3) * Vec3(-1, 0.5, 2).transpose();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const Eigen::Matrix3d& a : {rank1, Eigen::Matrix3d::Zero().eval(), Eigen::Matrix3d::Constant(nan).eval()}) {
    Eigen::Quaterniond q(random_rotation(rng));
    extract_rotation(a, q);
    EXPECT_TRUE(q.coeffs().allFinite());
    EXPECT_NEAR(q.norm(), 1.0, 1e-12);
  }
  // Rank 1 still maps its one direction onto the other.
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  extract_rotation(rank1, q, 200);
  EXPECT_NEAR((q * Vec3(-1, 0.5, 2).normalized() - Vec3(1, 2, 3).normalized()).norm(), 0.0, 1e-8);
}

TEST(Rotation, FitConditioningIsTheHessiansSmallestShare) {
  // Closed forms: the fit's Hessian is tr(S) I - sym(S) at its maximum S = R^T a.
  std::mt19937 rng(5);
  const Eigen::Quaterniond r(random_rotation(rng));
  const Eigen::Matrix3d rm = r.toRotationMatrix();
  const auto along = [](const Vec3& e) { return Eigen::Matrix3d(e * e.transpose()); };
  // Even in all directions: H = 2 I, a third each.
  EXPECT_NEAR(fit_conditioning(rm, r), 1.0 / 3.0, 1e-12);
  // A flat, even fan (edges along x and y): H = diag(1, 1, 2), a quarter.
  EXPECT_NEAR(fit_conditioning(rm * (along(Vec3::UnitX()) + along(Vec3::UnitY())), r), 0.25, 1e-12);
  // A fan stretched along x, four times y: H = diag(1, 4, 5), a tenth.
  EXPECT_NEAR(fit_conditioning(rm * (4.0 * along(Vec3::UnitX()) + along(Vec3::UnitY())), r), 0.1, 1e-12);
  // Edges along one line: the turn about it is free.
  EXPECT_NEAR(fit_conditioning(rm * along(Vec3(1, 2, 3)), r), 0.0, 1e-12);
  // Not at the maximum (a turned half-way round): no conditioning.
  EXPECT_EQ(fit_conditioning(-rm, r), 0.0);
}

}  // namespace
}  // namespace freeform
