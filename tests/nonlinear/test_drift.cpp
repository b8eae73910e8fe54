// DriftExtrapolation (nonlinear/drift.h) on maps whose iterates are known in closed form: a
// translation x <- x + v, a slide without end, is moved on by 8, 16, 32 and then 64 steps at a
// time; one that turns after a move falls back to 8; a contraction and an oscillation are
// never moved; a slow linear contraction still converges, in far fewer iterations.
#include "freeform/nonlinear/drift.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

using freeform::DriftExtrapolation;

namespace {

using Map = std::function<Eigen::VectorXd(const Eigen::VectorXd&, int)>;

// n iterations of x <- map(x, i) with the drift's moves; the stretch of each move.
std::vector<double> iterate(const Map& map, Eigen::VectorXd& x, int n) {
  DriftExtrapolation drift;
  std::vector<double> moves;
  for (int i = 0; i < n; ++i) {
    Eigen::VectorXd image = map(x, i);
    const double stretch = drift.stretch();
    if (drift.next(x, image)) moves.push_back(stretch);
    x = image;
  }
  return moves;
}

const Eigen::Vector3d v(1e-3, -2e-3, 0.5e-3);

}  // namespace

TEST(DriftExtrapolation, ASlideIsMovedOnEverFartherUpToTheCap) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  const auto moves = iterate([](const Eigen::VectorXd& y, int) -> Eigen::VectorXd { return y + v; }, x, 30);
  // A move after every 3 plain steps that slide on from the one before, each confirmed.
  EXPECT_EQ(moves, (std::vector<double>{8, 16, 32, 64, 64, 64, 64}));
  const double steps = 30 - 7 + (8 + 16 + 32 + 4 * 64);
  EXPECT_LT((x - steps * v).norm(), 1e-12);
}

TEST(DriftExtrapolation, ASlideThatTurnsAfterAMoveStartsOverFromTheFirstStretch) {
  const Eigen::Vector3d w(2e-3, 1e-3, 0.0);  // orthogonal to v
  ASSERT_NEAR(w.dot(v), 0.0, 1e-18);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(3);
  const auto moves =
      iterate([&](const Eigen::VectorXd& y, int i) -> Eigen::VectorXd { return y + (i < 4 ? v : w); }, x, 12);
  EXPECT_EQ(moves, (std::vector<double>{8, 8, 16}));
}

TEST(DriftExtrapolation, ConvergingAndOscillatingIterationsAreNotMoved) {
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3);
  EXPECT_TRUE(iterate([](const Eigen::VectorXd& y, int) -> Eigen::VectorXd { return 0.5 * y; }, x, 50).empty());
  x = Eigen::VectorXd::Ones(3);
  EXPECT_TRUE(iterate([](const Eigen::VectorXd& y, int) -> Eigen::VectorXd { return -0.9 * y; }, x, 50).empty());
}

TEST(DriftExtrapolation, ASlowContractionStillConvergesSooner) {
  // x <- 0.97 x: plain iteration needs log(1e-6) / log(0.97), about 454 iterations.
  const Map contract = [](const Eigen::VectorXd& y, int) -> Eigen::VectorXd { return 0.97 * y; };
  Eigen::VectorXd x = Eigen::VectorXd::Ones(3);
  DriftExtrapolation drift;
  int n = 0;
  for (; n < 454 && x.norm() > 1e-6 * std::sqrt(3.0); ++n) {
    Eigen::VectorXd image = contract(x, n);
    drift.next(x, image);
    x = image;
  }
  EXPECT_LE(x.norm(), 1e-6 * std::sqrt(3.0));
  EXPECT_LT(n, 454 / 2);
}
