// The factor's solve on all cores (issue 43; docs/benchmarks.md, "Precompute on all cores"):
// SparseSolver's subtree-parallel solve (numerics/supernodal_solve.h) against CHOLMOD's own, on
// the same factor of the BCM system of bench_scale's support (a libcgal-demo mesh subdivided S
// times, the first N free vertices breadth-first from vertex 0), alternating the two solves so
// that both see the same machine. Per column count: each solve's median and fastest wall time.
// The factorization too: ours (numerics/supernodal_factorization.h) against CHOLMOD's numeric
// factorization, alternating, and how far apart the two factors' solves are.
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
  // The factorization (ordering included) with ours and CHOLMOD's numeric factorization, alternating.
  std::vector<double> ours_ms, cholmod_ms;
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd probe(sys.a_pp.rows(), 3);
  for (Eigen::Index i = 0; i < probe.size(); ++i) probe.data()[i] = u(rng);
  double factor_difference = 0.0;
  for (int r = 0; r < repeats; ++r) {
    Eigen::SparseMatrix<double> copy = sys.a_pp;
    const PhaseClock c;
    const SparseSolver reference(std::move(copy), true, SolverKind::Auto, nullptr, FactorKernel::Cholmod);
    cholmod_ms.push_back(c.elapsed().wall_ms);
    copy = sys.a_pp;
    const PhaseClock o;
    const SparseSolver subtrees(std::move(copy), true);
    ours_ms.push_back(o.elapsed().wall_ms);
    const Eigen::MatrixXd y = reference.solve(probe, false, SolveKernel::Cholmod);
    factor_difference = std::max(
        factor_difference, (subtrees.solve(probe, false, SolveKernel::Cholmod) - y).cwiseAbs().maxCoeff() /
                               y.cwiseAbs().maxCoeff());
  }
  const SparseSolver solver(std::move(sys.a_pp), true);
  nlohmann::json out = {
      {"rows", solver.rows()},
      {"factor_nonzeros", solver.factor_nonzeros()},
      {"threads", thread_budget()},
      {"subtrees", solver.parallel_subtrees()},
      {"serial_share", solver.serial_solve_share()},
      {"factorization_ms",
       {{"subtrees", {{"median", bench::median(ours_ms)}, {"min", *std::min_element(ours_ms.begin(), ours_ms.end())}}},
        {"cholmod",
         {{"median", bench::median(cholmod_ms)}, {"min", *std::min_element(cholmod_ms.begin(), cholmod_ms.end())}}},
        {"max_relative_difference_of_a_solve", factor_difference}}}};
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
