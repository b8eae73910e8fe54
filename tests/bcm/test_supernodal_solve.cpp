// numerics/supernodal_solve.h through SparseSolver on BCM's own k = 1..3 systems: the subtrees
// solved concurrently give CHOLMOD's own solution to rounding, a small backward error, and the
// same bits on any number of threads.
#include "bcm_fixtures.h"

#include "freeform/bcm/bcm_system.h"
#include "freeform/common/parallel.h"
#include "freeform/numerics/sparse_solver.h"

#if FREEFORM_TEST_HAVE_CHOLMOD
#include <Eigen/CholmodSupport>
#endif

namespace freeform::test {
namespace {

TEST(SupernodalSolve, AgreesWithCholmodsOwnSolveToRounding) {
  for (int order : {1, 2, 3}) {
    for (int cells : {6, 90}) {
      SCOPED_TRACE("order " + std::to_string(order) + ", " + std::to_string(cells) + " cells");
      PlaneSystem sys(cells, order);
      const Eigen::SparseMatrix<double> full = sys.a;
      const SparseSolver solver(std::move(sys.a), true);
      if (solver.kind() != SolverKind::CholmodSupernodal) GTEST_SKIP() << "no CHOLMOD in this build";
      for (int m : {1, 3, 7, 8, 13}) {  // 4- and 8-wide chunks, padded and not
        const Eigen::MatrixXd b = random_rhs(full.rows(), m, 11u * static_cast<unsigned>(m));
        const Eigen::MatrixXd x = solver.solve(b);
        const Eigen::MatrixXd reference = solver.solve(b, true, SolveKernel::Cholmod);
        EXPECT_LE((x - reference).cwiseAbs().maxCoeff(), 1e-9 * reference.cwiseAbs().maxCoeff()) << m << " columns";
        const Eigen::MatrixXd baseline = solver.solve(b, true, SolveKernel::Baseline);
        EXPECT_LE((baseline - reference).cwiseAbs().maxCoeff(), 1e-9 * reference.cwiseAbs().maxCoeff()) << m;
        const double backward = (full * x - b).norm() / b.norm();
        EXPECT_LT(backward, 1e-7) << m << " columns";  // k = 3 at 8,000 rows: CHOLMOD's own is ~5e-9
        EXPECT_LE(backward, 10.0 * std::max((full * reference - b).norm() / b.norm(), 1e-16));
      }
    }
  }
}

TEST(SupernodalSolve, SplitsLargeFactorsIntoSubtreesAndGivesTheSameBitsOnEveryRun) {
  PlaneSystem sys(90, 3);
  const SparseSolver solver(std::move(sys.a), true);
  if (solver.kind() != SolverKind::CholmodSupernodal) GTEST_SKIP() << "no CHOLMOD in this build";
  // 8,000 rows: split until no subtree holds more than 1/64 of the factor.
  EXPECT_GE(solver.parallel_subtrees(), 32);
  // What stays serial is the top of the tree: the last separators, a small share of the factor.
  EXPECT_GT(solver.serial_solve_share(), 0.0);
  EXPECT_LT(solver.serial_solve_share(), 0.25);
  const Eigen::MatrixXd b = random_rhs(solver.rows(), 7, 5);
  const Eigen::MatrixXd first = solver.solve(b);
  // The pool takes the subtrees in whatever order its threads get to them; the sums must not care.
  for (int run = 0; run < 5; ++run) EXPECT_EQ(solver.solve(b), first) << "run " << run;
}

TEST(SupernodalSolve, SmallFactorsAreOneSubtree) {
  PlaneSystem sys(4, 1);
  const SparseSolver solver(std::move(sys.a), true);
  if (solver.kind() != SolverKind::CholmodSupernodal) GTEST_SKIP() << "no CHOLMOD in this build";
  EXPECT_GE(solver.parallel_subtrees(), 1);
  const Eigen::MatrixXd b = random_rhs(solver.rows(), 2, 3);
  EXPECT_LE((solver.solve(b) - solver.solve(b, true, SolveKernel::Cholmod)).cwiseAbs().maxCoeff(), 1e-12);
}

#if FREEFORM_TEST_HAVE_CHOLMOD
// SparseSolver makes CHOLMOD's permuted copy of the matrix itself, on all cores, and touches the
// factor's pages first (numerics/permuted_lower.h): with CHOLMOD's numeric factorization
// (FactorKernel::Cholmod) the factor must be CHOLMOD's own, bit for bit,
// so CHOLMOD's solve with it gives the same bits as Eigen's plain CHOLMOD factorization.
TEST(SupernodalSolve, FactorIsCholmodsOwnBitForBit) {
  for (int order : {1, 2, 3}) {
    SCOPED_TRACE("order " + std::to_string(order));
    PlaneSystem sys(60, order);
    const Eigen::SparseMatrix<double> lower = sys.a.triangularView<Eigen::Lower>();
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> reference(lower);
    ASSERT_EQ(reference.info(), Eigen::Success);
    const SparseSolver solver(std::move(sys.a), true, SolverKind::Auto, nullptr, FactorKernel::Cholmod);
    ASSERT_EQ(solver.kind(), SolverKind::CholmodSupernodal);
    const Eigen::MatrixXd b = random_rhs(solver.rows(), 3, 17);
    const Eigen::MatrixXd want = reference.solve(b);
    EXPECT_EQ(solver.solve(b, true, SolveKernel::Cholmod), want);
  }
}
#endif

}  // namespace
}  // namespace freeform::test
