#include "freeform/bcm/refinement.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"
#include "freeform/numerics/csr.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace freeform {
namespace {

using Ld = long double;
// Uninitialized: each array is first touched by the parallel loop that fills it.
using LdVector = std::vector<Ld, UninitializedAllocator<Ld>>;
using RowSp = Eigen::SparseMatrix<double, Eigen::RowMajor>;

constexpr std::ptrdiff_t kGrain = 1024;

// f(i) for the rows [0, rows) on the pool.
template <class F>
void for_rows(int rows, const F& f) {
  parallel_for(rows, kGrain, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto i = static_cast<int>(lo); i < hi; ++i) f(i);
  });
}

// next(r, :) = sum_c lap(r, c) w(c) z(c, :) for rows [0, rows), row-major d columns. Each row is
// zeroed by the thread that sums it: a serial fill (and, the first time, the page faults of a
// fresh allocation) kept one core busy and the others idle on large supports.
void level_product(const RowSp& lap, const double* w, const LdVector& z, int rows, int d, LdVector& next) {
  next.resize(static_cast<std::size_t>(rows) * static_cast<std::size_t>(d));
  parallel_for(rows, kGrain, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (auto r = static_cast<int>(lo); r < hi; ++r) {
      Ld* out = next.data() + static_cast<std::ptrdiff_t>(r) * d;
      std::fill(out, out + d, 0.0L);
      for (RowSp::InnerIterator it(lap, r); it; ++it) {
        const auto c = static_cast<std::ptrdiff_t>(it.col());
        const Ld f = static_cast<Ld>(it.value()) * (w ? static_cast<Ld>(w[c]) : 1.0L);
        const Ld* zc = z.data() + c * d;
        for (int j = 0; j < d; ++j) out[j] += f * zc[j];
      }
    }
  });
}

}  // namespace

Refinement refine_bcm_solution(const BcmSystem& sys, const SparseSolver& solver, const Eigen::MatrixXd& xc,
                               Eigen::MatrixXd& x, const Progress& progress, double rel_tol, int max_steps) {
  const int k = static_cast<int>(sys.level_weights.size()) + 1;
  const int n_free = static_cast<int>(x.rows());
  const int n_c = static_cast<int>(xc.rows());
  const int d = static_cast<int>(x.cols());
  if (sys.ring_rows.size() != static_cast<std::size_t>(k) + 1 || sys.ring_rows[0] != n_free ||
      sys.lap.cols() != n_free + n_c || xc.cols() != d)
    throw InvalidInput("refine_bcm_solution: the solution does not match the system's sizes");
  const double sign = k % 2 == 1 ? -1.0 : 1.0;  // A = sign * S_k

  // z: the patch's values, row-major, long double: the free rows (the iterate, updated in
  // place), then the constrained ones.
  LdVector z(static_cast<std::size_t>(n_free + n_c) * static_cast<std::size_t>(d)), next;
  const auto at = [d](int i, int j) { return static_cast<std::size_t>(i) * static_cast<std::size_t>(d) + j; };
  for_rows(n_c, [&](int i) {
    for (int j = 0; j < d; ++j) z[at(n_free + i, j)] = xc(i, j);
  });
  for_rows(n_free, [&](int i) {
    for (int j = 0; j < d; ++j) z[at(i, j)] = x(i, j);
  });

  Eigen::VectorXd scale = x.cwiseAbs().colwise().maxCoeff().transpose();
  for (Eigen::Index j = 0; j < scale.size(); ++j)
    if (!(scale[j] > 0.0)) scale[j] = 1.0;
  Refinement out;
  out.correction = out.initial = Eigen::VectorXd::Zero(d);
  double previous = HUGE_VAL;
  Eigen::MatrixXd r(n_free, d);
  LdVector level;
  for (int step = 0; step < max_steps; ++step) {
    progress.check();
    // S_k [x; xc] level by level: rows shrink ring by ring down to the free set.
    const LdVector* cur = &z;
    for (int m = 1; m <= k; ++m) {
      const double* w = m == 1 ? nullptr : sys.level_weights[static_cast<std::size_t>(m - 2)].data();
      level_product(sys.lap, w, *cur, sys.ring_rows[static_cast<std::size_t>(k - m)], d, m % 2 ? next : level);
      cur = m % 2 ? &next : &level;
    }
    for_rows(n_free, [&](int i) {
      for (int j = 0; j < d; ++j) r(i, j) = static_cast<double>(-sign * (*cur)[at(i, j)]);
    });
    const Eigen::MatrixXd dx = solver.solve(r, false);
    const Eigen::VectorXd size = dx.cwiseAbs().colwise().maxCoeff().transpose();
    const double worst = size.cwiseQuotient(scale).maxCoeff();
    if (!(worst <= previous)) break;  // diverging (or not finite): keep the last iterate
    for_rows(n_free, [&](int i) {
      for (int j = 0; j < d; ++j) z[at(i, j)] += dx(i, j);
    });
    if (out.steps++ == 0) out.initial = size;
    out.correction = size;
    if (worst <= rel_tol) {
      out.converged = true;
      break;
    }
    if (worst > 0.5 * previous) break;  // stagnating at the residual's own rounding, or diverging
    previous = worst;
  }
  for_rows(n_free, [&](int i) {
    for (int j = 0; j < d; ++j) x(i, j) = static_cast<double>(z[at(i, j)]);
  });
  return out;
}

}  // namespace freeform
