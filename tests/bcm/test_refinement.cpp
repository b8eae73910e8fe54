// refine_bcm_solution (bcm/refinement.h): from a perturbed start it recovers the solve, for the
// symmetric and the unsymmetric systems, and it stops (not converged, not blown up) when its
// corrections do not shrink; a cancel stops it between steps.
#include "bcm_fixtures.h"

#include "freeform/bcm/bcm_system.h"
#include "freeform/bcm/refinement.h"
#include "freeform/common/error.h"

#include <atomic>
#include <random>

namespace freeform::test {
namespace {

struct Problem {
  BcmSystem sys;
  Eigen::MatrixXd xc, exact;
};

Problem problem(int order, double outer) {
  BumpyScene scene;
  BcmSettings s;
  s.order = order;
  s.smoothness.outer = outer;
  Problem p{assemble_bcm_system(scene.mesh, scene.mesh.positions(), scene.regions(), s), {}, {}};
  p.xc.resize(static_cast<Eigen::Index>(p.sys.constrained.size()), 3);
  for (std::size_t j = 0; j < p.sys.constrained.size(); ++j)
    p.xc.row(static_cast<Eigen::Index>(j)) = scene.mesh.position(p.sys.constrained[j]).transpose() + Eigen::RowVector3d(0.0, 0.0, 0.1 * static_cast<double>(j % 3));
  p.exact = SparseSolver(Eigen::SparseMatrix<double>(p.sys.a_pp), p.sys.symmetric).solve(-(p.sys.a_pc * p.xc));
  return p;
}

Eigen::MatrixXd perturbed(const Eigen::MatrixXd& x, double size) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-size, size);
  return x.unaryExpr([&](double v) { return v + u(rng); });
}

TEST(Refinement, RecoversTheSolutionFromAPerturbedStart) {
  for (const auto& [order, outer] : {std::pair{2, 1.0}, std::pair{3, 2.0}, std::pair{3, 1.5}}) {
    SCOPED_TRACE(testing::Message() << "k = " << order << ", c = " << outer);
    const Problem p = problem(order, outer);
    const SparseSolver solver(Eigen::SparseMatrix<double>(p.sys.a_pp), p.sys.symmetric);
    Eigen::MatrixXd x = perturbed(p.exact, 1e-3);
    const Refinement r = refine_bcm_solution(p.sys, solver, p.xc, x);
    EXPECT_TRUE(r.converged);
    EXPECT_GE(r.steps, 2);  // the first correction removes the perturbation, the next one shows it did
    EXPECT_LT((x - p.exact).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(r.correction.maxCoeff(), 1e-11);
  }
}

TEST(Refinement, StopsWithoutConvergingWhenCorrectionsGrow) {
  // A factorization of 0.4 A overshoots every correction by 2.5: the error grows by 1.5 per step.
  const Problem p = problem(2, 1.0);
  const SparseSolver solver(Eigen::SparseMatrix<double>(0.4 * p.sys.a_pp), p.sys.symmetric);
  Eigen::MatrixXd x = perturbed(p.exact, 1e-3);
  const Refinement r = refine_bcm_solution(p.sys, solver, p.xc, x);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.steps, 1);  // the second, larger correction is refused
  EXPECT_GT(r.correction.maxCoeff(), 1e-4);  // the estimate shows the trouble
  EXPECT_TRUE(x.allFinite());
  EXPECT_LT((x - p.exact).cwiseAbs().maxCoeff(), 2e-3);
}

TEST(Refinement, RefusesMismatchedSizes) {
  const Problem p = problem(2, 1.0);
  const SparseSolver solver(Eigen::SparseMatrix<double>(p.sys.a_pp), p.sys.symmetric);
  Eigen::MatrixXd x = p.exact.topRows(p.exact.rows() - 1);
  EXPECT_THROW(refine_bcm_solution(p.sys, solver, p.xc, x), InvalidInput);
}

TEST(Refinement, CancelStopsItBeforeAStep) {
  const Problem p = problem(3, 2.0);
  const SparseSolver solver(Eigen::SparseMatrix<double>(p.sys.a_pp), p.sys.symmetric);
  const Eigen::MatrixXd start = perturbed(p.exact, 1e-3);
  Eigen::MatrixXd x = start;
  std::atomic<bool> cancel{true};
  Progress progress;
  progress.cancel = &cancel;
  EXPECT_THROW(refine_bcm_solution(p.sys, solver, p.xc, x, progress), Cancelled);
  EXPECT_EQ(x, start) << "a step ran after the cancel";
  cancel = false;
  EXPECT_TRUE(refine_bcm_solution(p.sys, solver, p.xc, x, progress).converged);
}

}  // namespace
}  // namespace freeform::test
