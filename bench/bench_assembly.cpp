// The BCM system's assembly on all cores (issue 43; docs/benchmarks.md, "Precompute on all
// cores"): assemble_bcm_system and the symmetry check SparseSolver makes, on bench_scale's
// support (a libcgal-demo mesh subdivided S times, the first N free vertices breadth-first from
// vertex 0). Run it with FREEFORM_THREADS=1 and without to see how the assembly scales
// (scripts/bench-assembly.sh does both). Per step: median wall and CPU time of the repeats.
// Args: mesh_name subdivisions free_in_thousands k [repeats]. JSON on stdout.
#include "bench_meshes.h"

#include "freeform/bcm/bcm_system.h"
#include "freeform/common/parallel.h"
#include "freeform/common/phase_clock.h"
#include "freeform/mesh/mesh.h"
#include "freeform/numerics/sparse_solver.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

using namespace freeform;

int main(int argc, char** argv) {
  const bench::ScaleSupport scene =
      bench::scale_support_from_args(argc, argv, "bench_assembly mesh_name subdivisions free_in_thousands k [repeats]");
  const Mesh& mesh = scene.mesh;
  const Regions regions(mesh, scene.support, {{scene.handle(), true}});
  const int repeats = argc > 5 ? std::stoi(argv[5]) : 3;
  BcmSettings settings;
  settings.order = std::stoi(argv[4]);
  nlohmann::json out = {{"threads", thread_budget()}};
  for (const bool split : {false, true}) {
    std::vector<double> wall, cpu, check_wall, check_cpu;
    for (int r = 0; r < repeats; ++r) {
      const PhaseClock clock;
      const BcmSystem sys = assemble_bcm_system(mesh, mesh.positions(), regions, settings, split);
      const PhaseTime t = clock.elapsed();
      wall.push_back(t.wall_ms);
      cpu.push_back(t.cpu_ms);
      const PhaseClock check;
      if (!is_symmetric(sys.a_pp, 1e-10)) std::fprintf(stderr, "A_pp is not symmetric\n");
      const PhaseTime c = check.elapsed();
      check_wall.push_back(c.wall_ms);
      check_cpu.push_back(c.cpu_ms);
      out["rows"] = sys.a_pp.rows();
      out["nonzeros"] = sys.a_pp.nonZeros();
    }
    out[split ? "assembly_split_operator" : "assembly"] = {{"wall_ms", bench::median(wall)},
                                                           {"cpu_ms", bench::median(cpu)}};
    if (!split) out["symmetry_check"] = {{"wall_ms", bench::median(check_wall)}, {"cpu_ms", bench::median(check_cpu)}};
  }
  std::cout << out.dump(1) << "\n";
}
