// A factored sparse square matrix, solved for many right-hand sides (one wrapper
// hides CHOLMOD / UMFPACK / Eigen). Symmetric positive definite -> CHOLMOD supernodal
// Cholesky (fallback Eigen LDLT); unsymmetric -> UMFPACK (fallback Eigen SparseLU).
#pragma once

#include "freeform/numerics/solver_kind.h"

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <string>

namespace freeform {

// True if |A - A^T| <= tol * max|A| entrywise (A square, compressed).
bool is_symmetric(const Eigen::SparseMatrix<double>& a, double tol = 1e-12);

// The symbolic half of a Cholesky SparseSolver: CHOLMOD's fill-reducing ordering and supernodal
// structure, from a pattern alone (a lower triangle, compressed; values unused). It can run on
// another thread while A's values are assembled (bcm/bcm_analysis.h). SparseSolver uses it when
// CHOLMOD factors A and A's lower triangle has exactly this pattern; otherwise it analyzes A.
class CholeskyAnalysis {
 public:
  explicit CholeskyAnalysis(const Eigen::SparseMatrix<double>& lower_pattern);
  ~CholeskyAnalysis();
  bool ok() const;  // false: no SuiteSparse in this build, the analysis failed, or already used

 private:
  friend class SparseSolver;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// How a CHOLMOD factor is solved: Auto, its subtrees on several cores (supernodal_solve.h) where
// its layout allows; Baseline, the same without the AVX2 kernels; Cholmod, CHOLMOD's own solve,
// one supernode after the other. The last two are for tests and benchmarks.
enum class SolveKernel { Auto, Baseline, Cholmod };
// How a CHOLMOD factor's values are computed: Auto, its subtrees on several cores
// (supernodal_factorization.h) where two threads are free (common/held_threads.h), else
// CHOLMOD's; Cholmod, always CHOLMOD's own numeric factorization (for tests and benchmarks).
enum class FactorKernel { Auto, Cholmod };

class SparseSolver {
 public:
  // Factors A. `symmetric` selects the family; `kind` forces one solver (Auto: the fast one,
  // with the Eigen fallback if the SuiteSparse one is unavailable or fails to factor; a forced
  // SuiteSparse kind in a build without SuiteSparse uses its Eigen counterpart).
  // Throws SolverError with a clear message if the matrix is singular, has non-finite entries
  // or (for Cholesky) is not positive definite; InvalidInput if it is not square, is declared
  // symmetric but is not (tolerance 1e-10), or a Cholesky kind is forced on an unsymmetric one.
  // The solver takes A's storage (kept for residuals; a Cholesky solver keeps only its lower
  // triangle): pass std::move(a), or a copy the caller still needs. Eigen 3.4's SparseMatrix has
  // no move constructor, so a by-value A would be copied (443 MB twice at 1M free, k = 3).
  // `analysis` (optional) is consumed: its CHOLMOD object becomes this solver's if A matches.
  SparseSolver(Eigen::SparseMatrix<double>&& a, bool symmetric, SolverKind kind = SolverKind::Auto,
               CholeskyAnalysis* analysis = nullptr, FactorKernel factor_kernel = FactorKernel::Auto);
  ~SparseSolver();
  SparseSolver(SparseSolver&&) noexcept;
  SparseSolver& operator=(SparseSolver&&) noexcept;

  // X = A^-1 B (B: n by m). Throws SolverError if the result is not finite or (check_residual)
  // its relative residual |A x - b| / |b| exceeds 1e-6 in some column after up to 8 steps of
  // iterative refinement with A (taken only when the first solve misses that bound, while they
  // lower it) and its normwise backward error |A x - b| / (|A|_F |x| + |b|) exceeds 1e-12
  // (numerically singular matrix; an ill-conditioned one solved stably passes, and its caller
  // judges the accuracy). Corrections of iterative refinement skip the check: their right-hand
  // side is itself rounding noise. residual (optional) receives relative_residual(X, B).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b, bool check_residual = true, SolveKernel kernel = SolveKernel::Auto,
                        double* residual = nullptr) const;

  // max over columns of |A x_j - b_j| / |b_j| (|A x_j - b_j| where b_j = 0).
  double relative_residual(const Eigen::MatrixXd& x, const Eigen::MatrixXd& b) const;

  SolverKind kind() const;
  Eigen::Index rows() const;
  // Subtrees solve() runs concurrently (supernodal_solve.h); 0 where CHOLMOD's own solve is used.
  int parallel_subtrees() const;
  double serial_solve_share() const;  // the factor's share solved on one thread (0 without subtrees)
  std::string name() const;  // e.g. "cholmod-supernodal-llt"
  bool reused_analysis() const;  // the factorization used the CholeskyAnalysis passed in
  // CHOLMOD only (else empty / 0): how its rows were ordered ("amd", "metis", "metis, N parts
  // in parallel") and the factor's nonzeros.
  std::string ordering() const;
  double factor_nonzeros() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  Eigen::MatrixXd solve_once(const Eigen::MatrixXd& b, SolveKernel kernel) const;
};

}  // namespace freeform
