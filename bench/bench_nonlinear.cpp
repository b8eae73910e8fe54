// The nonlinear model against CGAL's Surface_mesh_deformation (ARAP, spokes and rims) on the
// survey's large-deformation set-ups (tests/nonlinear/survey_shapes.h), in one run: time to
// convergence (precompute and solve separately), folded edges, smallest singular value of the
// face deformation gradients, enclosed volume. Prints JSON (docs/benchmarks.md).
//   bench_nonlinear [repetitions=3]
#include "build_paths.h"
#include "nonlinear/survey_shapes.h"

#include "freeform/edit/edit_solver.h"
#include "freeform/mesh/folds.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <vector>

#ifdef FREEFORM_HAVE_CGAL
#include "nonlinear/cgal_arap.h"
#endif

namespace {

using namespace freeform;
using namespace freeform::test;
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

nlohmann::json quality(const Shape& s, const VertexData<Vec3>& p) {
  return {{"folded_edges", count_folded_edges(s.mesh, s.mesh.positions(), p)},
          {"min_singular_value", min_singular_value(s.mesh, s.mesh.positions(), p)},
          {"volume_ratio", volume(s.mesh, p) / volume(s.mesh, s.mesh.positions())}};
}

// acceleration: NonlinearOptions::acceleration (0: plain local/global iteration, for comparison).
nlohmann::json run_freeform(Shape s, int order, int acceleration, int reps) {
  s.edit.settings.order = order;
  s.edit.deformation = Deformation::Nonlinear;
  s.edit.nonlinear.max_iterations = 1000;
  s.edit.nonlinear.acceleration = acceleration;
  std::vector<double> pre, solve;
  VertexData<Vec3> p = s.mesh.positions();
  NonlinearState state;
  for (int r = 0; r < reps; ++r) {
    auto t = Clock::now();
    const EditSolver solver(s.mesh, s.edit);
    pre.push_back(ms_since(t));
    p = s.mesh.positions();
    t = Clock::now();
    solver.evaluate(solver.transforms(s.edit), p);
    solve.push_back(ms_since(t));
    state = *solver.nonlinear_state();
  }
  nlohmann::json j = {{"method", acceleration > 0 ? "freeform nonlinear" : "freeform nonlinear, plain iteration"},
                      {"order", order}, {"precompute_ms", median(pre)},
                      {"solve_ms", median(solve)}, {"iterations", state.iterations}, {"converged", state.converged}};
  j.update(quality(s, p));
  return j;
}

#ifdef FREEFORM_HAVE_CGAL
nlohmann::json run_cgal_arap(const Shape& s, int reps) {
  std::vector<double> pre, solve;
  VertexData<Vec3> p = s.mesh.positions();
  for (int r = 0; r < reps; ++r) {
    const std::optional<PeerResult> peer = cgal_deform(s, 20000);  // to convergence
    if (!peer) return {{"method", "CGAL ARAP"}, {"error", "preprocess failed"}};
    pre.push_back(peer->precompute_ms);
    solve.push_back(peer->solve_ms);
    p = peer->positions;
  }
  nlohmann::json j = {{"method", "CGAL ARAP"}, {"precompute_ms", median(pre)}, {"solve_ms", median(solve)}};
  j.update(quality(s, p));
  return j;
}
#endif

}  // namespace

int main(int argc, char** argv) {
  const int reps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const char* env = std::getenv("FREEFORM_MESH_DIR");
  std::vector<Shape> shapes{bar_twist(), cylinder_bend()};
  if (auto cactus = cactus_bend(env && *env ? env : freeform::build_paths::default_mesh_dir()))
    shapes.push_back(std::move(*cactus));
  nlohmann::json out = nlohmann::json::array();
  for (const Shape& s : shapes) {
    nlohmann::json runs = nlohmann::json::array();
    for (int k : {2, 3}) {
      runs.push_back(run_freeform(s, k, NonlinearOptions{}.acceleration, reps));
      runs.push_back(run_freeform(s, k, 0, reps));
    }
#ifdef FREEFORM_HAVE_CGAL
    runs.push_back(run_cgal_arap(s, reps));
#endif
    out.push_back({{"test", s.name}, {"vertices", s.mesh.n_vertices()}, {"runs", runs}});
  }
  std::cout << out.dump(2) << "\n";
}
