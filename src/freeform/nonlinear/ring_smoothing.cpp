#include "freeform/nonlinear/ring_smoothing.h"

#include "freeform/common/parallel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace freeform {
namespace {

// Below this many passes the power is kept (a Chebyshev filter of the same width saves little).
constexpr int kChebyshevMinPasses = 16;
// The filter's largest response below its pass band, relative to the top of the spectrum.
constexpr double kRipple = 1e-3;
constexpr int kPowerIterations = 20;
constexpr std::ptrdiff_t kGrain = 1024;

struct Band {
  double centre = 0.0, half = 1.0, ripple = 0.0;
};

// T_m(y) / T_m(y0), y = (lambda - centre) / half, keeps [lo, cut] below 1 / T_m(y0) and rises to 1
// at `top`. The cut is chosen so that the response's slope at the top, T_m'(y0) / (half T_m(y0)),
// is the power's, n / top: near the smoothest modes both fall off alike, so both kernels have
// the same width. Infeasible (ripple 1) when even a cut at the top is not steep enough.
Band chebyshev_band(int n, int m, double top, double lo) {
  const double want = n / top;
  const auto slope = [&](double cut) {
    const double half = 0.5 * (cut - lo), t = std::acosh((top - 0.5 * (cut + lo)) / half);
    return m * std::tanh(m * t) / (half * std::sinh(t));
  };
  double a = lo, b = top;
  if (!(top > lo) || slope(top - 1e-9 * (top - lo)) < want) return {top - 1.0, 1.0, 1.0};
  for (int it = 0; it < 100; ++it) (slope(0.5 * (a + b)) < want ? a : b) = 0.5 * (a + b);
  const double cut = 0.5 * (a + b), half = 0.5 * (cut - lo), centre = 0.5 * (cut + lo);
  return {centre, half, 1.0 / std::cosh(m * std::acosh((top - centre) / half))};
}

}  // namespace

RingSmoothing::RingSmoothing(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int passes)
    : n_(static_cast<int>(lap.rows())), passes_(passes) {
  offset_.assign(1, 0);
  for (int i = 0; i < n_; ++i) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(lap, i); it; ++it)
      if (it.col() != i && it.col() < n_) nbr_.push_back(static_cast<int>(it.col()));
    offset_.push_back(static_cast<int>(nbr_.size()));
  }
  if (passes_ >= kChebyshevMinPasses) design_filter();
}

std::vector<int> RingSmoothing::components(int& count) const {
  std::vector<int> comp(static_cast<std::size_t>(n_), -1), stack;
  count = 0;
  for (int s = 0; s < n_; ++s) {
    if (comp[static_cast<std::size_t>(s)] >= 0) continue;
    comp[static_cast<std::size_t>(s)] = count;
    for (stack.assign(1, s); !stack.empty();) {
      const auto i = static_cast<std::size_t>(stack.back());
      stack.pop_back();
      for (int k = offset_[i]; k < offset_[i + 1]; ++k) {
        const auto j = static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)]);
        if (comp[j] >= 0) continue;
        comp[j] = count;
        stack.push_back(static_cast<int>(j));
      }
    }
    ++count;
  }
  return comp;
}

void RingSmoothing::design_filter() {
  int count = 0;
  const std::vector<int> comp = components(count);
  const auto of = [&comp](std::size_t i) { return static_cast<std::size_t>(comp[i]); };
  // Each component's top eigenvalue: power iteration from the constant vector, which starts
  // close to the smoothest mode (its Rayleigh quotient, from below). A few steps suffice: the
  // design barely moves with the last digits of the top (the gallery's and the editor's
  // degrees are the same after 20 steps as after 100), and the steps are serial.
  std::vector<double> top(static_cast<std::size_t>(count)), xy(top.size()), xx(top.size());
  std::vector<double> x(static_cast<std::size_t>(n_), 1.0), y(x.size());
  for (int it = 0; it < kPowerIterations; ++it) {
    std::fill(xy.begin(), xy.end(), 0.0);
    std::fill(xx.begin(), xx.end(), 0.0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      y[i] = sum_at(x, i);
      xy[of(i)] += x[i] * y[i];
      xx[of(i)] += x[i] * x[i];
    }
    for (std::size_t c = 0; c < top.size(); ++c) top[c] = xy[c] / xx[c];
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = y[i] / top[of(i)];
  }
  // A lower bound of each spectrum, the larger of Gershgorin's, 1 - degree, and Collatz and
  // Wielandt's: x > 0 is now close to the Perron vector, A's spectral radius is at most
  // max (A x)_i / x_i, so no eigenvalue of I + A is below 2 - max (x + A x)_i / x_i.
  std::vector<double> gershgorin(top.size(), 1.0), collatz(top.size(), 2.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    gershgorin[of(i)] = std::min(gershgorin[of(i)], 1.0 - (offset_[i + 1] - offset_[i]));
    collatz[of(i)] = std::min(collatz[of(i)], 2.0 - sum_at(x, i) / x[i]);
  }
  // The lowest degree whose filter keeps every component's stop band below kRipple.
  for (int m = static_cast<int>(std::ceil(2.0 * std::sqrt(double(passes_)))); m < passes_; ++m) {
    std::vector<Band> bands(top.size());
    bool ok = true;
    for (std::size_t c = 0; c < top.size() && ok; ++c) {
      const double lo = std::max(gershgorin[c], collatz[c]);
      bands[c] = chebyshev_band(passes_, m, top[c], lo);
      ok = bands[c].ripple <= kRipple || top[c] - lo < 1e-9;  // an isolated vertex: any filter
    }
    if (!ok) continue;
    degree_ = m;
    centre_.resize(x.size());
    half_.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      centre_[i] = bands[of(i)].centre;
      half_[i] = bands[of(i)].half;
    }
    return;
  }
}

void RingSmoothing::apply(std::vector<Eigen::Matrix3d>& cov, std::vector<Eigen::Matrix3d>& work) const {
  work.resize(cov.size());
  if (degree_ == 0) {
    for (int pass = 0; pass < passes_; ++pass) {
      parallel_for(n_, kGrain, [&](std::ptrdiff_t a, std::ptrdiff_t b) {
        for (auto i = static_cast<std::size_t>(a); i < static_cast<std::size_t>(b); ++i) work[i] = sum_at(cov, i);
      });
      std::swap(cov, work);
    }
    return;
  }
  // The polynomial as a product over its roots r = centre + half cos(theta_j), taken from both
  // ends of the stop band in turn (the partial products then stay within a few powers of 2 of
  // each other): each factor (I + A - r) is one pass, at a pass's cost.
  for (int j = 0; j < degree_; ++j) {
    const int k = j % 2 == 0 ? j / 2 : degree_ - 1 - j / 2;
    const double cos_theta = std::cos(std::numbers::pi * (k + 0.5) / degree_);
    parallel_for(n_, kGrain, [&](std::ptrdiff_t a, std::ptrdiff_t b) {
      for (auto i = static_cast<std::size_t>(a); i < static_cast<std::size_t>(b); ++i)
        work[i] = sum_at(cov, i) - (centre_[i] + half_[i] * cos_theta) * cov[i];
    });
    std::swap(cov, work);
  }
}

}  // namespace freeform
