#include "freeform/nonlinear/ring_smoothing.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
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

std::vector<int> connected_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int& count) {
  const auto n = static_cast<int>(lap.rows());
  std::vector<int> comp(static_cast<std::size_t>(n), -1), stack;
  count = 0;
  for (int s = 0; s < n; ++s) {
    if (comp[static_cast<std::size_t>(s)] >= 0) continue;
    comp[static_cast<std::size_t>(s)] = count;
    for (stack.assign(1, s); !stack.empty();) {
      const int i = stack.back();
      stack.pop_back();
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(lap, i); it; ++it) {
        const auto j = static_cast<std::size_t>(it.col());
        if (it.col() == i || it.col() >= n || comp[j] >= 0) continue;
        comp[j] = count;
        stack.push_back(static_cast<int>(j));
      }
    }
    ++count;
  }
  return comp;
}

RingSmoothing::RingSmoothing(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int passes)
    : RingSmoothing(lap, std::vector<int>{passes}) {}

RingSmoothing::RingSmoothing(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, const std::vector<int>& passes)
    : n_(static_cast<int>(lap.rows())) {
  offset_.assign(1, 0);
  for (int i = 0; i < n_; ++i) {
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(lap, i); it; ++it)
      if (it.col() != i && it.col() < n_) nbr_.push_back(static_cast<int>(it.col()));
    offset_.push_back(static_cast<int>(nbr_.size()));
  }
  int count = 0;
  component_ = connected_rows(lap, count);
  if (passes.size() == 1)
    passes_.assign(static_cast<std::size_t>(count), passes[0]);
  else if (passes.size() == static_cast<std::size_t>(count))
    passes_ = passes;
  else
    throw InternalError("RingSmoothing: " + std::to_string(passes.size()) + " pass counts for " +
                        std::to_string(count) + " components");
  degree_.assign(static_cast<std::size_t>(count), 0);
  roots_.resize(static_cast<std::size_t>(count));
  design_filters();
}

int RingSmoothing::sums() const {
  int most = 0;
  for (std::size_t c = 0; c < degree_.size(); ++c) most = std::max(most, degree_[c] > 0 ? degree_[c] : passes_[c]);
  return most;
}

void RingSmoothing::design_filters() {
  const std::size_t count = degree_.size();
  if (std::none_of(passes_.begin(), passes_.end(), [](int p) { return p >= kChebyshevMinPasses; })) return;
  const auto of = [this](std::size_t i) { return static_cast<std::size_t>(component_[i]); };
  // Each component's top eigenvalue: power iteration from the constant vector, which starts
  // close to the smoothest mode (its Rayleigh quotient, from below). A few steps suffice: the
  // design barely moves with the last digits of the top (the gallery's and the editor's
  // degrees are the same after 20 steps as after 100), and the steps are serial.
  std::vector<double> top(count), xy(count), xx(count);
  std::vector<double> x(static_cast<std::size_t>(n_), 1.0), y(x.size());
  for (int it = 0; it < kPowerIterations; ++it) {
    std::fill(xy.begin(), xy.end(), 0.0);
    std::fill(xx.begin(), xx.end(), 0.0);
    for (std::size_t i = 0; i < x.size(); ++i) {
      y[i] = sum_at(x, i);
      xy[of(i)] += x[i] * y[i];
      xx[of(i)] += x[i] * x[i];
    }
    for (std::size_t c = 0; c < count; ++c) top[c] = xy[c] / xx[c];
    for (std::size_t i = 0; i < x.size(); ++i) x[i] = y[i] / top[of(i)];
  }
  // A lower bound of each spectrum, the larger of Gershgorin's, 1 - degree, and Collatz and
  // Wielandt's: x > 0 is now close to the Perron vector, A's spectral radius is at most
  // max (A x)_i / x_i, so no eigenvalue of I + A is below 2 - max (x + A x)_i / x_i.
  std::vector<double> gershgorin(count, 1.0), collatz(count, 2.0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    gershgorin[of(i)] = std::min(gershgorin[of(i)], 1.0 - (offset_[i + 1] - offset_[i]));
    collatz[of(i)] = std::min(collatz[of(i)], 2.0 - sum_at(x, i) / x[i]);
  }
  // Per component, the lowest degree whose filter keeps its stop band below kRipple.
  std::vector<Band> bands(count);
  for (std::size_t c = 0; c < count; ++c) {
    const int passes = passes_[c];
    if (passes < kChebyshevMinPasses) continue;
    const double lo = std::max(gershgorin[c], collatz[c]);
    for (int m = static_cast<int>(std::ceil(2.0 * std::sqrt(double(passes)))); m < passes; ++m) {
      bands[c] = chebyshev_band(passes, m, top[c], lo);
      if (bands[c].ripple > kRipple && top[c] - lo >= 1e-9) continue;  // an isolated vertex: any filter
      degree_[c] = m;
      // The roots r = centre + half cos(theta_j), taken from both ends of the stop band in turn
      // (the partial products then stay within a few powers of 2 of each other).
      for (int j = 0; j < m; ++j) {
        const int k = j % 2 == 0 ? j / 2 : m - 1 - j / 2;
        roots_[c].push_back(std::cos(std::numbers::pi * (k + 0.5) / m));
      }
      break;
    }
  }
  centre_.resize(x.size());
  half_.resize(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    centre_[i] = bands[of(i)].centre;
    half_[i] = bands[of(i)].half;
  }
}

void RingSmoothing::apply(std::vector<Eigen::Matrix3d>& cov, std::vector<Eigen::Matrix3d>& work) const {
  work.resize(cov.size());
  // Every component takes its own steps; one that has taken them all is carried along. A
  // Chebyshev step is a factor (I + A - r) of its polynomial, at a pass's cost.
  for (int j = 0, steps = sums(); j < steps; ++j) {
    parallel_for(n_, kGrain, [&](std::ptrdiff_t a, std::ptrdiff_t b) {
      for (auto i = static_cast<std::size_t>(a); i < static_cast<std::size_t>(b); ++i) {
        const auto c = static_cast<std::size_t>(component_[i]);
        if (degree_[c] > 0)
          work[i] = j < degree_[c]
                        ? Eigen::Matrix3d(sum_at(cov, i) -
                                          (centre_[i] + half_[i] * roots_[c][static_cast<std::size_t>(j)]) * cov[i])
                        : cov[i];
        else
          work[i] = j < passes_[c] ? sum_at(cov, i) : cov[i];
      }
    });
    std::swap(cov, work);
  }
}

}  // namespace freeform
