#include "freeform/nonlinear/ring_smoothing.h"

#include "freeform/common/error.h"

#include <gtest/gtest.h>

#include <vector>

namespace freeform {
namespace {

// A w x w grid triangulated with one diagonal per square (interior valence 6), as the pattern
// of a Laplacian; vertex (r, c) is r * w + c.
Eigen::SparseMatrix<double, Eigen::RowMajor> grid_pattern(int w) {
  std::vector<Eigen::Triplet<double>> t;
  const auto link = [&](int a, int b) {
    t.emplace_back(a, b, -1.0);
    t.emplace_back(b, a, -1.0);
  };
  for (int r = 0; r < w; ++r)
    for (int c = 0; c < w; ++c) {
      const int v = r * w + c;
      t.emplace_back(v, v, 6.0);
      if (c + 1 < w) link(v, v + 1);
      if (r + 1 < w) link(v, v + w);
      if (r + 1 < w && c + 1 < w) link(v, v + w + 1);
    }
  Eigen::SparseMatrix<double, Eigen::RowMajor> lap(w * w, w * w);
  lap.setFromTriplets(t.begin(), t.end());
  return lap;
}

// (I + A)^n of a unit impulse at v, summed by hand: the kernel the passes define.
std::vector<double> power_kernel(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int v, int n) {
  std::vector<double> x(static_cast<std::size_t>(lap.rows()), 0.0), y(x.size());
  x[static_cast<std::size_t>(v)] = 1.0;
  for (int pass = 0; pass < n; ++pass) {
    for (int i = 0; i < lap.rows(); ++i) {
      double s = 0.0;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(lap, i); e; ++e)
        s += x[static_cast<std::size_t>(e.col())];
      y[static_cast<std::size_t>(i)] = s;
    }
    std::swap(x, y);
  }
  return x;
}

std::vector<double> filter_kernel(const RingSmoothing& smoothing,
                                  const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int v) {
  std::vector<Eigen::Matrix3d> cov(static_cast<std::size_t>(lap.rows()), Eigen::Matrix3d::Zero()), work;
  cov[static_cast<std::size_t>(v)] = Eigen::Matrix3d::Identity();
  smoothing.apply(cov, work);
  std::vector<double> k(cov.size());
  for (std::size_t i = 0; i < cov.size(); ++i) {
    EXPECT_NEAR(cov[i](0, 1), 0.0, 1e-300);  // entries do not mix
    EXPECT_DOUBLE_EQ(cov[i](0, 0), cov[i](2, 2));
    k[i] = cov[i](0, 0);
  }
  return k;
}

std::vector<double> filter_kernel(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int v, int n,
                                  int* sums = nullptr) {
  const RingSmoothing smoothing(lap, n);
  if (sums) *sums = smoothing.sums();
  return filter_kernel(smoothing, lap, v);
}

// Second moment about the impulse, in squared grid steps.
double spread(const std::vector<double>& k, int w, int v) {
  double sum = 0.0, moment = 0.0;
  for (int i = 0; i < w * w; ++i) {
    const double dr = i / w - v / w, dc = i % w - v % w;
    sum += k[static_cast<std::size_t>(i)];
    moment += k[static_cast<std::size_t>(i)] * (dr * dr + dc * dc);
  }
  return moment / sum;
}

TEST(RingSmoothing, FewPassesAreThePowerItself) {
  const int w = 21, v = 10 * w + 10;
  const auto lap = grid_pattern(w);
  int sums = 0;
  const std::vector<double> power = power_kernel(lap, v, 9), filtered = filter_kernel(lap, v, 9, &sums);
  EXPECT_EQ(sums, 9);
  for (std::size_t i = 0; i < power.size(); ++i) EXPECT_EQ(power[i], filtered[i]) << i;
}

// Many passes: a Chebyshev filter with fewer sums and the same width, no ringing to speak of.
TEST(RingSmoothing, ManyPassesTakeFewerSumsForTheSameWidth) {
  const int w = 81, v = 40 * w + 40;
  const auto lap = grid_pattern(w);
  for (const int n : {16, 28, 47, 64}) {
    int sums = 0;
    const std::vector<double> power = power_kernel(lap, v, n), filtered = filter_kernel(lap, v, n, &sums);
    EXPECT_LE(sums, 0.65 * n) << n;  // 10, 14, 18, 21
    const double want = spread(power, w, v), got = spread(filtered, w, v);
    EXPECT_NEAR(got / want, 1.0, 0.03) << n << ": " << got << " against " << want;
    double positive = 0.0, negative = 0.0;
    for (const double k : filtered) (k > 0 ? positive : negative) += std::abs(k);
    EXPECT_LT(negative, 1e-2 * positive) << n;
  }
}

// Two grids side by side, w x w and small x small, as one pattern.
Eigen::SparseMatrix<double, Eigen::RowMajor> two_grids(int w, int small) {
  const auto big = grid_pattern(w), part = grid_pattern(small);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < big.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(big, i); e; ++e)
      t.emplace_back(i, e.col(), e.value());
  for (int i = 0; i < part.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator e(part, i); e; ++e)
      t.emplace_back(w * w + i, w * w + e.col(), e.value());
  Eigen::SparseMatrix<double, Eigen::RowMajor> both(w * w + small * small, w * w + small * small);
  both.setFromTriplets(t.begin(), t.end());
  return both;
}

// Separate parts of the graph are filtered each with its own spectrum: a small part next to a
// large one is smoothed like the same part alone.
TEST(RingSmoothing, ComponentsAreFilteredApart) {
  const int w = 41, small = 9;
  const auto part = grid_pattern(small), both = two_grids(w, small);
  const int v = 4 * small + 4;
  const std::vector<double> alone = filter_kernel(part, v, 20), joint = filter_kernel(both, w * w + v, 20);
  const double scale_alone = alone[static_cast<std::size_t>(v)],
               scale_joint = joint[static_cast<std::size_t>(w * w + v)];
  for (int i = 0; i < small * small; ++i)
    EXPECT_NEAR(joint[static_cast<std::size_t>(w * w + i)] / scale_joint,
                alone[static_cast<std::size_t>(i)] / scale_alone, 1e-9)
        << i;
}

// Each component with its own passes (the nonlinear model's parts of a support, part_settings.h):
// each is smoothed to the bit as alone with its passes, the power (below 16) or the Chebyshev
// filter (from 16), whichever the other takes.
TEST(RingSmoothing, EachComponentTakesItsOwnPasses) {
  const int w = 41, small = 9;
  const auto big = grid_pattern(w), part = grid_pattern(small), both = two_grids(w, small);
  const int in_big = 20 * w + 20, in_small = 4 * small + 4;
  EXPECT_THROW(RingSmoothing(both, std::vector<int>{3, 3, 3}), InternalError);  // two components
  for (const auto& [big_passes, small_passes] : {std::pair{9, 20}, std::pair{28, 5}, std::pair{3, 3}}) {
    const RingSmoothing joint(both, std::vector<int>{big_passes, small_passes});
    EXPECT_EQ(joint.sums(), std::max(RingSmoothing(big, big_passes).sums(), RingSmoothing(part, small_passes).sums()));
    const std::vector<double> big_alone = filter_kernel(big, in_big, big_passes),
                              small_alone = filter_kernel(part, in_small, small_passes),
                              big_joint = filter_kernel(joint, both, in_big),
                              small_joint = filter_kernel(joint, both, w * w + in_small);
    for (int i = 0; i < w * w; ++i)
      ASSERT_EQ(big_joint[static_cast<std::size_t>(i)], big_alone[static_cast<std::size_t>(i)])
          << big_passes << ", " << i;
    for (int i = 0; i < small * small; ++i)
      ASSERT_EQ(small_joint[static_cast<std::size_t>(w * w + i)], small_alone[static_cast<std::size_t>(i)])
          << small_passes << ", " << i;
  }
}

}  // namespace
}  // namespace freeform
