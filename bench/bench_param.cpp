// Anisotropic-bending precompute (docs/benchmarks.md, "Anisotropic parametrization"): the cost
// of the parametrization step (support grown by k rings, LSCM with CHOLMOD, principal axes,
// equalizing) that BcmSolver pays before assembly when settings.anisotropic is set, against
// the number of free vertices; and LSCM alone on the same patch.
//
// Mesh: make_bumpy_plane 640 x 640 (410k vertices, amplitude 0.05, frequency 3), a support disk
// about the centre holding N free vertices plus a central handle disk (N / 50 vertices); k = 2.
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/traversal.h"
#include "freeform/param/anisotropic.h"
#include "freeform/param/lscm.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <vector>

namespace {

using namespace freeform;

const Mesh& plane() {
  static const Mesh mesh = Mesh::from_soup(make_bumpy_plane(640, 640, 0.05, 3.0));
  return mesh;
}

// Support vertices (free + handle) of about n_free * 1.02 vertices: a disk about the centre.
const std::vector<Vertex>& support(int n_free) {
  static std::map<int, std::vector<Vertex>> cache;
  auto& s = cache[n_free];
  if (s.empty()) {
    const double h = 1.0 / 640.0;
    const double r = std::sqrt(1.02 * n_free / M_PI) * h;
    for (Vertex v : plane().vertices())
      if ((plane().position(v) - Vec3(0.5, 0.5, 0)).head<2>().norm() < r) s.push_back(v);
  }
  return s;
}

void BM_AnisotropicDomain(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const auto& s = support(n);
  AnisotropicDomain dom;
  for (auto _ : state) {
    dom = anisotropic_domain(plane(), s, 2);
    benchmark::DoNotOptimize(dom.positions);
  }
  if (!dom.used) state.SkipWithError(dom.fallback.c_str());
  state.counters["free"] = n;
  state.counters["patch_vertices"] = dom.patch_vertices;
  state.counters["angle_distortion_max"] = dom.angle_distortion_max;
}

void BM_Lscm(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const VertexData<int> dist = ring_distance(plane(), support(n), 2);
  TriangleSoup soup;
  std::vector<int> local(static_cast<std::size_t>(plane().n_vertices()), -1);
  for (Face f : plane().faces()) {
    const auto v = plane().vertices(f);
    if (dist[v[0]] < 0 || dist[v[1]] < 0 || dist[v[2]] < 0) continue;
    Tri t{};
    for (std::size_t c = 0; c < 3; ++c) {
      int& l = local[static_cast<std::size_t>(v[c].idx())];
      if (l < 0) {
        l = static_cast<int>(soup.positions.size());
        soup.positions.push_back(plane().position(v[c]));
      }
      t[c] = l;
    }
    soup.faces.push_back(t);
  }
  const Mesh patch = Mesh::from_soup(soup);
  for (auto _ : state) benchmark::DoNotOptimize(lscm(patch).uv);
  state.counters["patch_vertices"] = patch.n_vertices();
}

BENCHMARK(BM_AnisotropicDomain)->Arg(35000)->Arg(300000)->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(3)
    ->ReportAggregatesOnly(true);
BENCHMARK(BM_Lscm)->Arg(35000)->Arg(300000)->Unit(benchmark::kMillisecond)->Iterations(3)->Repetitions(3)
    ->ReportAggregatesOnly(true);

}  // namespace

BENCHMARK_MAIN();
