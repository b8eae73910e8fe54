// Iterative refinement of the BCM solve against the unassembled operator (issue 13).
//
// The assembled order-k matrix A = (-1)^k S_k is rounded once when it is formed, and its
// solution drifts from the true one like (diameter / edge)^(2k): measured on the armadillo
// (k = 3), 1.9e-6 of the bounding-box diagonal at 35k free vertices, 2e-4 at 140k, while the
// factored system's own residual stays near 1e-13. Here the residual is computed level by
// level from the factors (L, then Lam_m D L ...) in long double, so refinement with the same
// factorization converges to the solution of the true system (7.5e-12 after one step at 35k,
// 6e-14 after three at 140k, against a mixed-form reference: bench/bench_accuracy.cpp).
#pragma once

#include "freeform/bcm/bcm_system.h"
#include "freeform/common/progress.h"
#include "freeform/numerics/sparse_solver.h"

#include <Eigen/Core>

namespace freeform {

struct Refinement {
  int steps = 0;               // corrections applied
  bool converged = false;      // the last correction was below the tolerance
  Eigen::VectorXd correction;  // per column, max |dx| of the last correction (an error estimate)
  Eigen::VectorXd initial;     // the same of the first correction: the unrefined solve's error
};

// x: P by d, solutions of A_pp x = -A_pc xc from `solver` (a factorization of sys.a_pp; may
// be another factorization of the same system), improved in place. Stops when every column's
// correction is below rel_tol times the column's largest entry, when a correction no longer
// halves, or after max_steps. sys needs lap, level_weights and ring_rows (always assembled).
// progress is checked before each step (1.4 s each at 1M free, k = 3).
Refinement refine_bcm_solution(const BcmSystem& sys, const SparseSolver& solver, const Eigen::MatrixXd& xc,
                               Eigen::MatrixXd& x, const Progress& progress = {}, double rel_tol = 1e-12,
                               int max_steps = 8);

}  // namespace freeform
