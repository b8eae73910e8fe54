// Reference 3 (docs/references.md): continuous boundary smoothness c (docs/bcm.md).
// Planar annulus, handle = the k innermost circles lifted by h, support boundary near r = 1,
// flat fixed surface outside. The radial slope jump across the outer support boundary
//   jump = |slope(last free circle -> first fixed circle) - slope(first -> second fixed circle)|
// in units of the mean slope h / (R_out - R_in) must fall monotonically as c goes 0 -> k-1:
// c = 0 is a crease, c = k-1 a smooth junction whose jump shrinks under refinement.
#include "annulus_fixture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using namespace freeform;
using freeform::test::Annulus;

double mean_z(const Annulus& a, const VertexData<Vec3>& x, int circle) {
  double s = 0;
  for (Vertex v : a.circles(circle, circle)) s += x[v].z();
  return s / a.segments;
}

// Slope jump at the outer support boundary for smoothness c, in units of the mean slope.
double slope_jump(const Annulus& a, int k, double c) {
  int m = 0;  // last free circle: the outermost one with radius <= 1
  while (a.radius(m + 1) <= 1.0 + 1e-12) ++m;
  const double h = 1.0;
  const VertexData<Vec3> x = freeform::test::lift_inner_disk(a, k, m, h, c);
  const double inside = (mean_z(a, x, m + 1) - mean_z(a, x, m)) / (a.radius(m + 1) - a.radius(m));
  const double outside = (mean_z(a, x, m + 2) - mean_z(a, x, m + 1)) / (a.radius(m + 2) - a.radius(m + 1));
  return std::abs(inside - outside) / (h / (a.radius(m + 1) - a.radius(k - 1)));
}

void sweep(int k) {
  const Annulus coarse(0.25, 1.6, 96), fine(0.25, 1.6, 192);
  std::vector<double> jumps;
  for (double c = 0; c <= k - 1 + 1e-9; c += 0.25) {
    jumps.push_back(slope_jump(coarse, k, c));
    std::printf("[smoothness] k=%d c=%.2f segments=96 slope jump / mean slope = %.4e\n", k, c, jumps.back());
  }
  for (std::size_t i = 1; i < jumps.size(); ++i)
    EXPECT_LT(jumps[i], jumps[i - 1]) << "k=" << k << ": jump did not fall at c=" << 0.25 * static_cast<double>(i);
  const double smooth_fine = slope_jump(fine, k, k - 1);
  std::printf("[smoothness] k=%d c=%d segments=192 slope jump / mean slope = %.4e (ratio coarse/fine %.2f)\n", k,
              k - 1, smooth_fine, jumps.back() / smooth_fine);
  EXPECT_GT(jumps.front(), 0.5) << "c = 0 should be a crease";
  EXPECT_LT(jumps.back(), 0.25 * jumps.front()) << "c = k-1 should be much smoother than c = 0";
  EXPECT_LT(smooth_fine, 0.75 * jumps.back()) << "the smooth junction's jump must shrink under refinement";
}

TEST(BoundarySmoothness, SlopeJumpFallsMonotonicallyWithCForThinPlate) { sweep(2); }
TEST(BoundarySmoothness, SlopeJumpFallsMonotonicallyWithCForMinimalCurvatureVariation) { sweep(3); }

}  // namespace
