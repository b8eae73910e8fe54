// Multiresolution benchmarks (docs/benchmarks.md, "Multiresolution"): decomposition (base +
// encoding, excluding the BCM precomputation) and per-frame reconstruction (BCM basis product,
// base normals in the support and its first ring, detail) against the number of free vertices.
//
// Mesh: a fine bumpy plane (make_bumpy_plane, 12 periods, amplitude 1% of the width), support
// 0.1 <= x <= 0.9, one movable handle strip 0.45 <= x <= 0.55, order k = 2. Grid sizes are
// chosen for about 35k and 300k free vertices. Decomposition is reported as a counter
// (decomposition_ms) of the construction; the timed loop is evaluate() with a moved handle.
#include "freeform/mesh/generators.h"
#include "freeform/edit/edit_solver.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>

namespace {

using namespace freeform;

struct Setup {
  Mesh mesh;
  std::unique_ptr<EditSolver> solver;                 // the default: vertex frames on the BCM base
  std::unique_ptr<MultiresSolver> normal_encoding;    // normal displacement on the smooth operator shape
};

Setup& setup(int n) {
  static std::map<int, std::unique_ptr<Setup>> cache;
  auto& s = cache[n];
  if (!s) {
    s = std::make_unique<Setup>();
    s->mesh = Mesh::from_soup(make_bumpy_plane(n, n, 0.01, 12));
    Edit edit;  // multiresolution is the default
    edit.handles.emplace_back();
    for (Vertex v : s->mesh.vertices()) {
      const double x = s->mesh.position(v).x();
      if (x >= 0.1 && x <= 0.9) edit.support.push_back(v);
      if (x >= 0.45 && x <= 0.55) edit.handles[0].vertices.push_back(v);
    }
    s->solver = std::make_unique<EditSolver>(s->mesh, edit);
    MultiresOptions normal;
    normal.encoding = MultiresOptions::Encoding::Normal;
    s->normal_encoding = std::make_unique<MultiresSolver>(s->mesh, s->solver->regions(), edit.settings, normal);
  }
  return *s;
}

Eigen::Affine3d bend() {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.translation() = Vec3(0, 0, 0.1);
  t.rotate(Eigen::AngleAxisd(0.2, Vec3::UnitY()));
  return t;
}

void BM_MultiresReconstruct(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Affine3d> transforms{bend()};
  VertexData<Vec3> positions = s.mesh.positions();
  for (auto _ : state) {
    s.solver->evaluate(transforms, positions);
    benchmark::DoNotOptimize(positions.raw().data());
  }
  const MultiresStats& st = *s.solver->stats().multires;
  const MultiresProblems pr = s.solver->problems(positions).detail;
  state.counters["free"] = st.free;
  state.counters["decomposition_ms"] = st.decomposition_ms;
  state.counters["operator_shape_ms"] = st.operator_shape_ms;  // part of decomposition_ms
  state.counters["bcm_precompute_ms"] =
      s.solver->bcm().stats().assembly_ms + s.solver->bcm().stats().factorization_ms + s.solver->bcm().stats().basis_ms;
  state.counters["flipped"] = pr.flipped;
}

// The normal-displacement encoding (the nonlinear model's, and the linear default before
// vertex frames) on the same setup and edit.
void BM_MultiresReconstructNormalEncoding(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Affine3d> transforms{bend()};
  VertexData<Vec3> positions = s.mesh.positions();
  for (auto _ : state) {
    s.normal_encoding->evaluate(transforms, positions);
    benchmark::DoNotOptimize(positions.raw().data());
  }
  const MultiresStats& st = s.normal_encoding->stats();
  const MultiresProblems pr = s.normal_encoding->problems(positions);
  state.counters["decomposition_ms"] = st.decomposition_ms;
  state.counters["fallback"] = st.fallback;
  state.counters["flipped"] = pr.flipped;
  state.counters["overlaps"] = pr.overlaps;
}

// Both encodings alternated frame by frame, so that both see the same machine (this VM's speed
// drifts by half within seconds): per-frame medians and tenth percentiles, and their ratio.
void BM_MultiresEncodingsAlternated(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  const std::vector<Eigen::Affine3d> transforms{bend()};
  VertexData<Vec3> positions = s.mesh.positions();
  std::vector<double> frames, normal;
  const auto ms = [](auto f) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  };
  for (auto _ : state) {
    frames.push_back(ms([&] { s.solver->evaluate(transforms, positions); }));
    normal.push_back(ms([&] { s.normal_encoding->evaluate(transforms, positions); }));
    benchmark::DoNotOptimize(positions.raw().data());
  }
  const auto quantile = [](std::vector<double> v, double q) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1)), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
  };
  state.counters["frames_median_ms"] = quantile(frames, 0.5);
  state.counters["normal_median_ms"] = quantile(normal, 0.5);
  state.counters["frames_p10_ms"] = quantile(frames, 0.1);
  state.counters["normal_p10_ms"] = quantile(normal, 0.1);
  state.counters["ratio_median"] = quantile(frames, 0.5) / quantile(normal, 0.5);
  state.counters["ratio_p10"] = quantile(frames, 0.1) / quantile(normal, 0.1);
}

// Plain BCM evaluate on the same setup, for the cost of the detail on top of it.
void BM_BcmEvaluateSameSetup(benchmark::State& state) {
  Setup& s = setup(static_cast<int>(state.range(0)));
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.translation() = Vec3(0, 0, 0.1);
  const std::vector<Eigen::Affine3d> transforms{t};
  VertexData<Vec3> positions = s.mesh.positions();
  for (auto _ : state) {
    s.solver->bcm().evaluate(transforms, positions);
    benchmark::DoNotOptimize(positions.raw().data());
  }
}

// n = 222: 49.7k vertices, 35.1k free; n = 650: 424k vertices, 300k free.
BENCHMARK(BM_MultiresReconstruct)->Arg(222)->Arg(650)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MultiresReconstructNormalEncoding)->Arg(222)->Arg(650)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_MultiresEncodingsAlternated)->Arg(222)->Arg(650)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BcmEvaluateSameSetup)->Arg(222)->Arg(650)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
