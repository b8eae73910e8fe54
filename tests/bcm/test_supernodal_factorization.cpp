// numerics/supernodal_factorization.h through SparseSolver on BCM's own k = 1..3 systems: the
// subtrees factored concurrently give a factor whose solves have CHOLMOD's backward error and
// CHOLMOD's solution to rounding, the same bits on every run, and a matrix that is not positive
// definite is refused as CHOLMOD refuses it.
#include "bcm_fixtures.h"

#include "freeform/common/error.h"
#include "freeform/common/held_threads.h"
#include "freeform/common/parallel.h"
#include "freeform/numerics/sparse_solver.h"

namespace freeform::test {
namespace {

// Without a second thread SparseSolver keeps CHOLMOD's numeric factorization.
bool factors_on_subtrees() { return thread_budget() >= 2; }

TEST(SupernodalFactorization, SolvesAsAccuratelyAsCholmodsFactor) {
  if (!factors_on_subtrees()) GTEST_SKIP() << "one thread: CHOLMOD's own factorization";
  for (int order : {1, 2, 3}) {
    for (int cells : {6, 90}) {
      SCOPED_TRACE("order " + std::to_string(order) + ", " + std::to_string(cells) + " cells");
      PlaneSystem sys(cells, order);
      const Eigen::SparseMatrix<double> full = sys.a;
      Eigen::SparseMatrix<double> copy = sys.a;
      const SparseSolver ours(std::move(sys.a), true);
      const SparseSolver cholmod(std::move(copy), true, SolverKind::Auto, nullptr, FactorKernel::Cholmod);
      if (ours.kind() != SolverKind::CholmodSupernodal) GTEST_SKIP() << "no CHOLMOD in this build";
      const Eigen::MatrixXd b = random_rhs(full.rows(), 4, 23);
      const Eigen::MatrixXd x = ours.solve(b, true, SolveKernel::Cholmod);
      const Eigen::MatrixXd reference = cholmod.solve(b, true, SolveKernel::Cholmod);
      const double backward = (full * x - b).norm() / b.norm();
      const double reference_backward = (full * reference - b).norm() / b.norm();
      EXPECT_LE(backward, 10.0 * std::max(reference_backward, 1e-16));
      // Two backward-stable factors: their solutions differ by the condition number times
      // rounding, which the k = 3 operator at 8,000 rows raises to about 1e-9.
      EXPECT_LE(rel_diff(x, reference), order == 3 ? 1e-7 : 1e-10);
      // The factor works with the subtree solve as with CHOLMOD's.
      EXPECT_LE(rel_diff(ours.solve(b), x), 1e-9);
    }
  }
}

TEST(SupernodalFactorization, GivesTheSameBitsOnEveryRun) {
  if (!factors_on_subtrees()) GTEST_SKIP() << "one thread: CHOLMOD's own factorization";
  PlaneSystem sys(90, 2);
  const Eigen::MatrixXd b = random_rhs(sys.a.rows(), 3, 5);
  Eigen::SparseMatrix<double> copy = sys.a;
  const SparseSolver first(std::move(copy), true);
  ASSERT_GE(first.parallel_subtrees(), 32);
  const Eigen::MatrixXd want = first.solve(b, true, SolveKernel::Cholmod);
  // The threads take the subtrees in whatever order they get to them; the factor must not care.
  for (int run = 0; run < 3; ++run) {
    copy = sys.a;
    EXPECT_EQ(SparseSolver(std::move(copy), true).solve(b, true, SolveKernel::Cholmod), want) << "run " << run;
  }
}

// Beside a thread that long work holds (the ordering ahead) only the threads left are used: on 2
// cores that is one, and the factor is CHOLMOD's own, bit for bit.
TEST(SupernodalFactorization, LeavesTheCoresThatOtherWorkHolds) {
  const int budget = thread_budget();
  {
    const HeldThread held;
    EXPECT_EQ(threads_free(), std::max(1, budget - 1));
    if (budget == 2) {
      PlaneSystem sys(60, 2);
      const Eigen::MatrixXd b = random_rhs(sys.a.rows(), 2, 9);
      Eigen::SparseMatrix<double> copy = sys.a;
      const SparseSolver beside(std::move(copy), true);
      const SparseSolver cholmod(std::move(sys.a), true, SolverKind::Auto, nullptr, FactorKernel::Cholmod);
      EXPECT_EQ(beside.solve(b, true, SolveKernel::Cholmod), cholmod.solve(b, true, SolveKernel::Cholmod));
    }
  }
  EXPECT_EQ(threads_free(), budget);
}

TEST(SupernodalFactorization, RefusesAMatrixThatIsNotPositiveDefinite) {
  for (FactorKernel kernel : {FactorKernel::Auto, FactorKernel::Cholmod}) {
    PlaneSystem sys(60, 1);
    // A negative pivot deep in one subtree: some row's diagonal far below its off-diagonal sum.
    const Eigen::Index row = sys.a.rows() / 3;
    sys.a.coeffRef(row, row) = -sys.a.coeff(row, row);
    EXPECT_THROW(SparseSolver(std::move(sys.a), true, SolverKind::CholmodSupernodal, nullptr, kernel), SolverError);
  }
}

}  // namespace
}  // namespace freeform::test
