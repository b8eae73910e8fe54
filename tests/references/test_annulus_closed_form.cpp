// Reference 2 (docs/references.md): radially symmetric closed-form solutions of Lap^k z = 0 on
// a planar annulus. Handle = the k innermost circles lifted by h, fixed = the k outermost
// circles at z = 0, free in between; the k constrained circles on each side are flat, so they
// prescribe z = h (resp. 0) and k-1 vanishing radial derivatives.
//   k = 1: z = a + b ln r
//   k = 2: + c r^2 + d r^2 ln r
//   k = 3: + e r^4 + f r^4 ln r
// The discrete error max |z - z_exact| / h must fall under refinement.
#include "annulus_fixture.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using namespace freeform;
using freeform::test::Annulus;

// d-th derivative (d <= 2) of basis function j: 1, ln r, r^2, r^2 ln r, r^4, r^4 ln r.
double basis(int j, int d, double r) {
  const double l = std::log(r);
  switch (j * 3 + d) {
    case 0: return 1;
    case 1: case 2: return 0;
    case 3: return l;
    case 4: return 1 / r;
    case 5: return -1 / (r * r);
    case 6: return r * r;
    case 7: return 2 * r;
    case 8: return 2;
    case 9: return r * r * l;
    case 10: return 2 * r * l + r;
    case 11: return 2 * l + 3;
    case 12: return r * r * r * r;
    case 13: return 4 * r * r * r;
    case 14: return 12 * r * r;
    case 15: return r * r * r * r * l;
    case 16: return 4 * r * r * r * l + r * r * r;
    case 17: return 12 * r * r * l + 7 * r * r;
    default: return 0;
  }
}

// z(R1) = h, z(R2) = 0 and z^(d)(R1) = z^(d)(R2) = 0 for d = 1..k-1.
struct Exact {
  int k;
  Eigen::VectorXd coef;
  Exact(int k_, double r1, double r2, double h) : k(k_) {
    const int n = 2 * k;
    Eigen::MatrixXd m(n, n);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    for (int d = 0; d < k; ++d)
      for (int j = 0; j < n; ++j) {
        m(2 * d, j) = basis(j, d, r1);
        m(2 * d + 1, j) = basis(j, d, r2);
      }
    rhs(0) = h;
    coef = m.fullPivLu().solve(rhs);
  }
  double operator()(double r) const {
    double z = 0;
    for (int j = 0; j < 2 * k; ++j) z += coef(j) * basis(j, 0, r);
    return z;
  }
};

// Image of basis function j under the radial Laplacian f'' + f'/r, in the same basis:
// Lap 1 = Lap ln r = 0, Lap r^2 = 4, Lap r^2 ln r = 4 + 4 ln r, Lap r^4 = 16 r^2,
// Lap r^4 ln r = 8 r^2 + 16 r^2 ln r.
Eigen::Matrix<double, 6, 6> radial_laplacian() {
  Eigen::Matrix<double, 6, 6> m = Eigen::Matrix<double, 6, 6>::Zero();
  m(0, 2) = 4;
  m(0, 3) = 4, m(1, 3) = 4;
  m(2, 4) = 16;
  m(2, 5) = 8, m(3, 5) = 16;
  return m;
}

TEST(ExactSolution, SatisfiesTheBoundaryConditionsAndThePolyharmonicEquation) {
  // Guards the reference itself: the derivative table against central differences and against
  // the Laplacian table, then Lap^k z = 0 exactly in coefficient space and the conditions.
  const Eigen::Matrix<double, 6, 6> lap = radial_laplacian();
  for (double r : {0.3, 0.7, 1.0}) {
    for (int j = 0; j < 6; ++j) {
      const double e = 1e-5;
      EXPECT_NEAR(basis(j, 1, r), (basis(j, 0, r + e) - basis(j, 0, r - e)) / (2 * e), 1e-7) << j;
      EXPECT_NEAR(basis(j, 2, r), (basis(j, 1, r + e) - basis(j, 1, r - e)) / (2 * e), 1e-7) << j;
      double image = 0;
      for (int i = 0; i < 6; ++i) image += lap(i, j) * basis(i, 0, r);
      EXPECT_NEAR(basis(j, 2, r) + basis(j, 1, r) / r, image, 1e-12) << j;
    }
  }
  for (int k = 1; k <= 3; ++k) {
    const Exact z(k, 0.3, 1.0, 1.0);
    Eigen::Matrix<double, 6, 1> c = Eigen::Matrix<double, 6, 1>::Zero();
    c.head(2 * k) = z.coef;
    Eigen::Matrix<double, 6, 1> lap_k = c;
    for (int i = 0; i < k; ++i) lap_k = lap * lap_k;
    EXPECT_LT(lap_k.cwiseAbs().maxCoeff(), 1e-9 * c.cwiseAbs().maxCoeff()) << "k=" << k;
    EXPECT_NEAR(z(0.3), 1.0, 1e-12);
    EXPECT_NEAR(z(1.0), 0.0, 1e-12);
    for (int d = 1; d < k; ++d) {
      double at_inner = 0, at_outer = 0;
      for (int j = 0; j < 2 * k; ++j) at_inner += z.coef(j) * basis(j, d, 0.3), at_outer += z.coef(j) * basis(j, d, 1.0);
      EXPECT_NEAR(at_inner, 0.0, 1e-9);
      EXPECT_NEAR(at_outer, 0.0, 1e-9);
    }
  }
}

struct Row {
  int segments, free;
  double err_last, err_center;
};

// Effective boundary: "last" puts it on the innermost/outermost constrained circle next to the
// free region; "center" in the middle of each block of k constrained circles.
Row run(int k, int segments) {
  const Annulus a(0.25, 1.0, segments);
  const int last_free = a.rings - k;
  const double h = 1.0;
  Row row{segments, 0, 0, 0};
  const VertexData<Vec3> x = freeform::test::lift_inner_disk(a, k, last_free, h, k - 1, &row.free);
  auto mean_radius = [&](int first, int last) {
    double s = 0;
    for (int i = first; i <= last; ++i) s += a.radius(i);
    return s / (last - first + 1);
  };
  const Exact at_last(k, a.radius(k - 1), a.radius(last_free + 1), h);
  const Exact at_center(k, mean_radius(0, k - 1), mean_radius(last_free + 1, a.rings), h);
  for (Vertex v : a.circles(k, last_free)) {
    const double r = x[v].head<2>().norm();
    row.err_last = std::max(row.err_last, std::abs(x[v].z() - at_last(r)) / h);
    row.err_center = std::max(row.err_center, std::abs(x[v].z() - at_center(r)) / h);
  }
  return row;
}

// k = 1: the discrete solution is exactly a + b ln r (every band between two circles is a
// scaled copy of the previous one, cotangents are scale invariant, so the flux is the same
// through each band and z is linear in the circle index = ln r / ln q); only rounding remains.
// k = 2, 3: second order with the effective boundary in the middle of each block of k
// constrained circles (on the last constrained circle it is only first order, printed too).
constexpr double kFinalBound[4] = {1e-10, 1e-10, 3e-4, 7e-4};

TEST(AnnulusClosedForm, ErrorFallsUnderRefinementForEachOrder) {
  const std::vector<int> resolutions = {48, 96, 192, 384};
  for (int k = 1; k <= 3; ++k) {
    std::vector<Row> rows;
    for (int s : resolutions) rows.push_back(run(k, s));
    for (std::size_t i = 0; i < rows.size(); ++i) {
      const Row& r = rows[i];
      std::printf("[annulus] k=%d segments=%3d free=%6d  err(last ring)=%.3e rate=%5.2f  err(block centre)=%.3e "
                  "rate=%5.2f\n",
                  k, r.segments, r.free, r.err_last, i ? std::log2(rows[i - 1].err_last / r.err_last) : 0.0,
                  r.err_center, i ? std::log2(rows[i - 1].err_center / r.err_center) : 0.0);
    }
    if (k == 1) {
      for (const Row& r : rows) EXPECT_LT(r.err_center, kFinalBound[1]) << "k=1 segments=" << r.segments;
      continue;
    }
    for (std::size_t i = 1; i < rows.size(); ++i) {
      EXPECT_LT(rows[i].err_center, rows[i - 1].err_center) << "k=" << k << " error did not fall at " << rows[i].segments;
      EXPECT_GT(std::log2(rows[i - 1].err_center / rows[i].err_center), 1.5) << "k=" << k << " not second order";
    }
    EXPECT_LT(rows.back().err_center, kFinalBound[k]) << "k=" << k;
  }
}

}  // namespace
