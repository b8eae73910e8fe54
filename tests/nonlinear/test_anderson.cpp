// Anderson acceleration on fixed-point maps with a known fixed point: a linear contraction
// (where Anderson mixing with m >= dim is equivalent to GMRES, Walker & Ni 2011, so it must end
// in a handful of steps where plain iteration needs thousands) and a nonlinear one.
#include "freeform/nonlinear/anderson.h"

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <random>

namespace freeform {
namespace {

using Map = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

// Iterations until |G(x) - x| < tol (or `cap`), accelerated with depth m.
int iterations_to_converge(const Map& g_of, Eigen::VectorXd x, int m, double tol, int cap,
                           Eigen::VectorXd* out = nullptr) {
  AndersonAcceleration anderson(x.size(), m);
  for (int k = 1; k <= cap; ++k) {
    Eigen::VectorXd g = g_of(x);
    if ((g - x).norm() < tol) {
      if (out) *out = g;
      return k;
    }
    anderson.next(x, g);
    x = g;
  }
  if (out) *out = x;
  return cap;
}

TEST(AndersonAcceleration, SolvesALinearContractionInAFewSteps) {
  // G(x) = M x + c, M symmetric with eigenvalues in [0.5, 0.995]: plain iteration shrinks the
  // error by 0.995 per step.
  constexpr int n = 6;
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd q = Eigen::MatrixXd::NullaryExpr(n, n, [&] { return normal(rng); });
  q = Eigen::HouseholderQR<Eigen::MatrixXd>(q).householderQ();
  const Eigen::VectorXd eig = Eigen::VectorXd::LinSpaced(n, 0.5, 0.995);
  const Eigen::MatrixXd m = q * eig.asDiagonal() * q.transpose();
  const Eigen::VectorXd c = Eigen::VectorXd::NullaryExpr(n, [&] { return normal(rng); });
  const Eigen::VectorXd exact = (Eigen::MatrixXd::Identity(n, n) - m).partialPivLu().solve(c);
  const Map g = [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return m * x + c; };

  Eigen::VectorXd accelerated, plain;
  const int fast = iterations_to_converge(g, Eigen::VectorXd::Zero(n), 8, 1e-10, 10000, &accelerated);
  const int slow = iterations_to_converge(g, Eigen::VectorXd::Zero(n), 0, 1e-10, 10000, &plain);
  EXPECT_LE(fast, 3 * n);
  EXPECT_GT(slow, 2000);  // log(1e-10 / |f0|) / log(0.995)
  EXPECT_LT((accelerated - exact).norm(), 1e-7 * exact.norm());
  EXPECT_LT((plain - exact).norm(), 1e-6 * exact.norm());
}

TEST(AndersonAcceleration, ConvergesOnANonlinearMapToItsFixedPoint) {
  // G(x)_i = cos(x_i) / 20 + 0.47 (x_{i-1} + x_{i+1}): a contraction (Lipschitz 0.99 in the
  // max norm); the fixed point is checked by its residual, not against the plain run.
  constexpr int n = 40;
  const Map g = [](const Eigen::VectorXd& x) -> Eigen::VectorXd {
    Eigen::VectorXd y(x.size());
    for (Eigen::Index i = 0; i < n; ++i) y(i) = 0.05 * std::cos(x(i)) + 0.47 * (x((i + n - 1) % n) + x((i + 1) % n));
    return y;
  };
  Eigen::VectorXd fixed;
  const int fast = iterations_to_converge(g, Eigen::VectorXd::Zero(n), 5, 1e-12, 1000, &fixed);
  const int slow = iterations_to_converge(g, Eigen::VectorXd::Zero(n), 0, 1e-12, 1000);
  EXPECT_LT((g(fixed) - fixed).norm(), 1e-12);
  EXPECT_LT(fast * 3, slow) << fast << " / " << slow;
}

// Why NonlinearSolver confirms convergence with a plain step: a secant method also lands on a
// fixed point that repels plain iteration. G(x) = 2x - 1 (fixed point 1, derivative 2).
TEST(AndersonAcceleration, FindsFixedPointsThatRepelPlainIteration) {
  const auto g_of = [](double x) { return 2.0 * x - 1.0; };
  AndersonAcceleration a(1, 3);
  Eigen::VectorXd x = Eigen::VectorXd::Constant(1, 1.001), g(1);
  g(0) = g_of(x(0));
  a.next(x, g);  // nothing to combine yet: the plain image, which moves away
  EXPECT_NEAR(g(0), 1.002, 1e-12);
  x = g;
  g(0) = g_of(x(0));
  // Its residual grew (0.001 -> 0.002): the safeguard drops the history, a plain step again.
  EXPECT_FALSE(a.next(x, g));
  EXPECT_NEAR(g(0), 1.004, 1e-12);
  // Once two images whose residual shrank are combined, the secant step lands exactly on
  // the repelling fixed point.
  AndersonAcceleration b(1, 3);
  Eigen::VectorXd y = Eigen::VectorXd::Constant(1, 1.004), h(1);
  h(0) = g_of(y(0));
  b.next(y, h);
  y = Eigen::VectorXd::Constant(1, 1.002);  // a smaller residual: recorded, then combined
  h(0) = g_of(y(0));
  EXPECT_TRUE(b.next(y, h));
  EXPECT_NEAR(h(0), 1.0, 1e-12);
}

TEST(AndersonAcceleration, DepthZeroIsPlainIterationAndAResetForgetsTheHistory) {
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3), g = Eigen::VectorXd::Constant(3, 2.0);
  AndersonAcceleration none(3, 0);
  EXPECT_FALSE(none.next(x, g));
  EXPECT_EQ(g, Eigen::VectorXd::Constant(3, 2.0));

  AndersonAcceleration a(3, 4);
  EXPECT_FALSE(a.next(x, g));  // a first image has nothing to combine with
  Eigen::VectorXd x2 = g, g2 = Eigen::VectorXd::Constant(3, 2.5);
  EXPECT_TRUE(a.next(x2, g2));
  Eigen::VectorXd x3 = g2, g3 = Eigen::VectorXd::Constant(3, 2.6);
  EXPECT_FALSE(a.next(x3, g3, false));  // recorded, not combined: the plain image stays
  EXPECT_EQ(g3, Eigen::VectorXd::Constant(3, 2.6));
  a.reset();
  g3 = Eigen::VectorXd::Constant(3, 2.7);
  EXPECT_FALSE(a.next(g2, g3));
  EXPECT_EQ(g3, Eigen::VectorXd::Constant(3, 2.7));
}

}  // namespace
}  // namespace freeform
