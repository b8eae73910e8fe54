// Accuracy of the order-k BCM solve against the support's size (issue 13; docs/benchmarks.md).
// The scene of tests/bcm/accuracy_scene.h (armadillo subdivided twice, 416k vertices, a
// breadth-first support, the handle translated). Per size: BcmSolver's precompute timings and
// refinement, and against the independent mixed-form reference (tests/bcm/mixed_reference.h)
// the error of the plain factored solve and of BcmSolver's refined one, relative to the
// bounding-box diagonal. One JSON line per size. Args: k [blended 0/1] sizes in thousands...
#include "accuracy_scene.h"

#include "freeform/bcm/bcm_system.h"
#include "freeform/numerics/sparse_solver.h"

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <string>

using namespace freeform;

namespace {

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: bench_accuracy k blended(0/1) size_in_thousands...\n");
    return 2;
  }
  BcmSettings s;
  s.order = std::stoi(argv[1]);
  if (std::stoi(argv[2]) != 0) s.smoothness.outer = s.order - 1.5;
  const test::AccuracyMesh& m = test::accuracy_mesh();
  for (int a = 3; a < argc; ++a) {
    const int n = std::stoi(argv[a]) * 1000;
    const auto t0 = std::chrono::steady_clock::now();
    const test::AccuracyResult r = test::accuracy_at(n, s);
    const double total_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    // The plain factored solve, for the "before" column: same system, no refinement.
    const int h = std::max(50, n / 50);
    const Regions regions(m.mesh, std::vector<Vertex>(m.bfs.begin(), m.bfs.begin() + h + n),
                          {HandleRegion{std::vector<Vertex>(m.bfs.begin(), m.bfs.begin() + h), true}});
    const BcmSystem sys = assemble_bcm_system(m.mesh, m.mesh.positions(), regions, s);
    Eigen::MatrixXd xc(sys.constrained.size(), 3);
    const Vec3 shift = Vec3(0.1, 0.2, 0.05) * m.diagonal;
    for (std::size_t j = 0; j < sys.constrained.size(); ++j)
      xc.row(static_cast<Eigen::Index>(j)) =
          (m.mesh.position(sys.constrained[j]) + (regions.handle_of(sys.constrained[j]) >= 0 ? shift : Vec3::Zero())).transpose();
    const Eigen::MatrixXd plain =
        SparseSolver(Eigen::SparseMatrix<double>(sys.a_pp), sys.symmetric).solve(-(sys.a_pc * xc));
    VertexData<Vec3> boundary = m.mesh.positions();
    for (int i = 0; i < h; ++i) boundary[m.bfs[static_cast<std::size_t>(i)]] += shift;
    const double c = s.smoothness.outer == Smoothness::kDefault ? s.order - 1.0 : s.smoothness.outer;
    const Eigen::MatrixXd ref = test::mixed_form_reference(m.mesh, regions, s.order, boundary, c, s.order - 1.0);
    const double plain_error = (plain - ref).rowwise().norm().maxCoeff() / m.diagonal;
    const BcmStats& st = r.stats;
    std::printf(
        "{\"k\": %d, \"blended\": %s, \"free\": %d, \"solver\": \"%s\", \"assembly_ms\": %.0f, \"factorization_ms\": %.0f, "
        "\"basis_ms\": %.0f, \"refinement_ms\": %.0f, \"refinement_steps\": %d, \"converged\": %s, "
        "\"forward_error_estimate\": %.3g, \"error\": %.3g, \"unrefined_error\": %.3g, \"residual\": %.3g, "
        "\"peak_rss_mb\": %.0f, \"wall_s_with_reference\": %.1f}\n",
        s.order, s.smoothness.outer == Smoothness::kDefault ? "false" : "true", st.free, st.solver.c_str(), st.assembly_ms,
        st.factorization_ms, st.basis_ms, st.refinement_ms, st.refinement_steps, st.refinement_converged ? "true" : "false",
        st.forward_error, r.error, plain_error, st.residual, peak_rss_mb(), total_s);
    std::fflush(stdout);
  }
}
