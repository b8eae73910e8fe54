// The factor's solve on all cores (issue 43; docs/benchmarks.md, "Precompute on all cores"):
// SparseSolver's subtree-parallel solve (numerics/supernodal_solve.h) against CHOLMOD's own, on
// the same factor of the BCM system of bench_scale's support (a libcgal-demo mesh subdivided S
// times, the first N free vertices breadth-first from vertex 0), alternating the two solves so
// that both see the same machine. Per column count: each solve's median and fastest wall time.
// The numeric factorization too: ours (numerics/supernodal_factorization.h) against CHOLMOD's,
// alternating after the same analysis, and the two factors' solves (backward errors, difference).
// Args: mesh_name subdivisions free_in_thousands k [repeats]. JSON on stdout.
#include "bench_meshes.h"

#include "freeform/bcm/bcm_system.h"
#include "freeform/common/parallel.h"
#include "freeform/common/phase_clock.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/numerics/sparse_solver.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>
#include <random>
#include <string>

using namespace freeform;

int main(int argc, char** argv) {
  const bench::ScaleSupport scene =
      bench::scale_support_from_args(argc, argv, "bench_solve mesh_name subdivisions free_in_thousands k [repeats]");
  const Mesh& mesh = scene.mesh;
  const Regions regions(mesh, scene.support, {{scene.handle(), true}});
  const int repeats = argc > 5 ? std::stoi(argv[5]) : 5;
  BcmSettings settings;
  settings.order = std::stoi(argv[4]);
  BcmSystem sys = assemble_bcm_system(mesh, mesh.positions(), regions, settings, false);
  // The numeric factorization (after the same analysis, made apart) with ours and CHOLMOD's,
  // alternating, and the backward error of a solve with each factor.
  std::vector<double> ours_ms, cholmod_ms;
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd probe(sys.a_pp.rows(), 3);
  for (Eigen::Index i = 0; i < probe.size(); ++i) probe.data()[i] = u(rng);
  const Eigen::SparseMatrix<double> lower = sys.a_pp.triangularView<Eigen::Lower>();
  double factor_difference = 0.0, ours_residual = 0.0, cholmod_residual = 0.0;
  std::vector<double> analysis_ms;
  const auto factor = [&](FactorKernel kernel, std::vector<double>& ms, double& residual) {
    const PhaseClock analysing;
    CholeskyAnalysis analysis(lower);
    analysis_ms.push_back(analysing.elapsed().wall_ms);
    Eigen::SparseMatrix<double> copy = sys.a_pp;
    const PhaseClock clock;
    SparseSolver solver(std::move(copy), true, SolverKind::Auto, &analysis, kernel);
    ms.push_back(clock.elapsed().wall_ms);
    const Eigen::MatrixXd x = solver.solve(probe, false, SolveKernel::Cholmod);
    residual = std::max(residual, solver.relative_residual(x, probe));
    return x;
  };
  for (int r = 0; r < repeats; ++r) {
    const Eigen::MatrixXd y = factor(FactorKernel::Cholmod, cholmod_ms, cholmod_residual);
    const Eigen::MatrixXd x = factor(FactorKernel::Auto, ours_ms, ours_residual);
    factor_difference = std::max(factor_difference, (x - y).cwiseAbs().maxCoeff() / y.cwiseAbs().maxCoeff());
  }
  const SparseSolver solver(std::move(sys.a_pp), true);
  nlohmann::json out = {
      {"rows", solver.rows()},
      {"factor_nonzeros", solver.factor_nonzeros()},
      {"threads", thread_budget()},
      {"subtrees", solver.parallel_subtrees()},
      {"serial_share", solver.serial_solve_share()},
      {"analysis_ms", bench::median(analysis_ms)},
      {"factorization_ms",
       {{"subtrees", {{"median", bench::median(ours_ms)}, {"min", *std::min_element(ours_ms.begin(), ours_ms.end())}}},
        {"cholmod",
         {{"median", bench::median(cholmod_ms)}, {"min", *std::min_element(cholmod_ms.begin(), cholmod_ms.end())}}},
        {"max_relative_difference_of_a_solve", factor_difference},
        {"backward_error", {{"subtrees", ours_residual}, {"cholmod", cholmod_residual}}}}}};
  for (int m : {3, 7}) {
    Eigen::MatrixXd b(solver.rows(), m);
    for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = u(rng);
    std::vector<double> ours, cholmod;
    double difference = 0.0;
    for (int r = 0; r < repeats; ++r) {
      const PhaseClock a;
      const Eigen::MatrixXd x = solver.solve(b, false);
      ours.push_back(a.elapsed().wall_ms);
      const PhaseClock c;
      const Eigen::MatrixXd y = solver.solve(b, false, SolveKernel::Cholmod);
      cholmod.push_back(c.elapsed().wall_ms);
      difference = std::max(difference, (x - y).cwiseAbs().maxCoeff() / y.cwiseAbs().maxCoeff());
    }
    out["columns"].push_back(
        {{"columns", m},
         {"subtrees_ms", {{"median", bench::median(ours)}, {"min", *std::min_element(ours.begin(), ours.end())}}},
         {"cholmod_ms",
          {{"median", bench::median(cholmod)}, {"min", *std::min_element(cholmod.begin(), cholmod.end())}}},
         {"max_relative_difference", difference}});
  }
  std::cout << out.dump(1) << "\n";
}
