// The fill-reducing ordering of the BCM system on all cores (issue 43; docs/benchmarks.md,
// "Precompute on all cores"): METIS on the whole graph (what CHOLMOD runs, one thread) against
// numerics/nested_dissection.h with 2..64 parts, on bench_scale's support (a libcgal-demo mesh
// subdivided S times, the first N free vertices breadth-first from vertex 0). Per variant: wall
// and CPU time on this machine, the factor's nonzeros, and each task's own time, from which the
// ordering's wall time on `parts` cores follows: the splits level by level (the largest of each
// level), then the largest part. At k = 1 (Laplacian-like: the multiresolution's membrane fill)
// AMD, as the solver uses there, orders the whole graph and the parts.
// Args: mesh_name subdivisions free_in_thousands k [parts...]. JSON on stdout.
#include "bench_meshes.h"

#include "freeform/bcm/bcm_analysis.h"
#include "freeform/common/parallel.h"
#include "freeform/common/phase_clock.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/numerics/nested_dissection.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

using namespace freeform;

int main(int argc, char** argv) {
  const bench::ScaleSupport scene = bench::scale_support_from_args(
      argc, argv, "bench_ordering mesh_name subdivisions free_in_thousands k [parts...]");
  const Mesh& mesh = scene.mesh;
  const Regions regions(mesh, scene.support, {{scene.handle(), true}});
  const int k = std::stoi(argv[4]);
  const Eigen::SparseMatrix<double> lower = bcm_lower_pattern(mesh, regions, k);
  const LeafOrdering how = k == 1 ? LeafOrdering::Amd : LeafOrdering::Metis;
  nlohmann::json out = {{"rows", lower.rows()}, {"nonzeros", lower.nonZeros()}, {"threads", thread_budget()}};
  {
    const PhaseClock clock;
    const double fill = cholesky_fill(lower, {}, how);  // the ordering + the symbolic analysis
    const PhaseTime t = clock.elapsed();
    out["whole_graph"] = {{"wall_ms", t.wall_ms}, {"cpu_ms", t.cpu_ms}, {"factor_nonzeros", fill}};
  }
  for (int a = 5; a < argc; ++a) {
    const int parts = std::stoi(argv[a]);
    DissectionTimes times;
    const PhaseClock clock;
    const std::vector<int> perm = nested_dissection(lower, parts, &times, how);
    const PhaseTime ordering = clock.elapsed();
    const PhaseClock analysis;
    const double fill = cholesky_fill(lower, perm);
    const PhaseTime symbolic = analysis.elapsed();
    double on_own_cores = 0;
    for (const auto& level : times.split_ms) on_own_cores += *std::max_element(level.begin(), level.end());
    on_own_cores += *std::max_element(times.leaf_ms.begin(), times.leaf_ms.end());
    out["parts"].push_back({{"parts", parts},
                            {"ordering_wall_ms", ordering.wall_ms},
                            {"ordering_cpu_ms", ordering.cpu_ms},
                            {"split_ms", times.split_ms},
                            {"leaf_ms", times.leaf_ms},
                            {"ordering_on_parts_cores_ms", on_own_cores},
                            {"symbolic_analysis_ms", symbolic.wall_ms},
                            {"factor_nonzeros", fill}});
  }
  std::cout << out.dump(1) << "\n";
}
