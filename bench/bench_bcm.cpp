// BCM engine benchmarks (docs/benchmarks.md, "BCM engine"): the precomputation (assembly,
// factorization, basis) and the per-frame evaluate against the number of free vertices, for
// k = 1, 2, 3 with uniform (c = k-1) and blended (fractional c; unsymmetric for k = 3)
// smoothness. Peers on the same region: CGAL::Polygon_mesh_processing::fair (a tool without
// precomputation pays it every frame) and CGAL::Surface_mesh_deformation (ARAP; preprocess and
// one deform() iteration). Run through scripts/bench-bcm.sh, which prints JSON with medians.
//
// Mesh: armadillo.off (libcgal-demo, 26k vertices, closed) with two 1-to-4 midpoint
// subdivisions (416k vertices). Support: the first N + H vertices of a breadth-first order
// from a seed; handle: the first H of them (H = max(50, N / 50)); free = N.
#include "bench_meshes.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/traversal.h"
#include "freeform/regions/regions.h"

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <vector>

#ifdef FREEFORM_HAVE_CGAL
#include <CGAL/Polygon_mesh_processing/fair.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>
#endif

void eigen_plain_product(const double* x0, const double* basis, const double* g, double* x, long rows,
                         long n4);  // bench/peer_product.cpp (column-major)

namespace {

using namespace freeform;

using bench::mesh_dir;
using bench::subdivide_midpoint;

struct BenchMesh {
  TriangleSoup soup;
  Mesh mesh;
  std::vector<Vertex> bfs;  // breadth-first order from the seed
};

const BenchMesh& bench_mesh() {
  static const BenchMesh m = [] {
    BenchMesh b;
    const auto path = mesh_dir() / "armadillo.off";
    if (!std::filesystem::exists(path)) throw std::runtime_error("missing " + path.string() + "; run scripts/fetch-data.sh");
    b.soup = subdivide_midpoint(subdivide_midpoint(read_mesh(path.string()).soup));
    b.mesh = Mesh::from_soup(b.soup);
    const Vertex seed[] = {Vertex(1000)};
    b.bfs = k_ring(b.mesh, seed, 100000);
    return b;
  }();
  return m;
}

struct Region {
  std::vector<Vertex> support, handle;
};

Region region(int free_count) {
  const BenchMesh& m = bench_mesh();
  const int h = std::max(50, free_count / 50);
  if (static_cast<std::size_t>(free_count + h) >= m.bfs.size()) throw std::runtime_error("support larger than the mesh");
  Region r;
  r.handle.assign(m.bfs.begin(), m.bfs.begin() + h);
  r.support.assign(m.bfs.begin(), m.bfs.begin() + h + free_count);
  std::sort(r.handle.begin(), r.handle.end());
  std::sort(r.support.begin(), r.support.end());  // sorted: set_difference below
  return r;
}

BcmSettings settings_for(int k, bool blended) {
  BcmSettings s;
  s.order = k;
  if (blended) {  // fractional c on the outer boundary: k = 2 -> 0.5; k = 3 -> 1.5, i.e.
                  // lambda_1 = 1, lambda_2 = 0.5 (unsymmetric, LU)
    s.smoothness.outer = k == 3 ? 1.5 : 0.5;
    s.smoothness.inner = k - 1;
  }
  return s;
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

// The benchmark's edit: plain BCM (multiresolution off) on region(free_count).
Edit edit_for(int free_count, int k, bool blended) {
  const Region r = region(free_count);
  Edit e;
  e.settings = settings_for(k, blended);
  e.multiresolution = false;
  e.support = r.support;
  e.handles.push_back(EditHandle{r.handle, true, {}, {}});
  return e;
}

std::map<std::tuple<int, int, bool>, std::unique_ptr<EditSolver>>& solver_cache() {
  static std::map<std::tuple<int, int, bool>, std::unique_ptr<EditSolver>> cache;
  return cache;
}

// The precomputed solver of a case (BM_BcmPrecompute's, or built now).
const EditSolver& cached_solver(int free_count, int k, bool blended) {
  auto& cache = solver_cache();
  auto it = cache.find({free_count, k, blended});
  if (it == cache.end())
    it = cache.emplace(std::make_tuple(free_count, k, blended),
                       std::make_unique<EditSolver>(bench_mesh().mesh, edit_for(free_count, k, blended))).first;
  return *it->second;
}

// Args: free vertices in thousands, k, blended (0/1).
void BM_BcmPrecompute(benchmark::State& state) {
  const int free_count = static_cast<int>(state.range(0)) * 1000;
  const int k = static_cast<int>(state.range(1));
  const bool blended = state.range(2) != 0;
  const BenchMesh& m = bench_mesh();
  const Edit edit = edit_for(free_count, k, blended);
  BcmStats stats;
  for (auto _ : state) {
    auto solver = std::make_unique<EditSolver>(m.mesh, edit);
    stats = solver->stats().bcm;
    // Kept for BM_BcmEvaluate: the solver holds only the dense basis (7 doubles per free vertex).
    solver_cache()[{free_count, k, blended}] = std::move(solver);
  }
  state.counters["free"] = stats.free;
  state.counters["assembly_ms"] = stats.assembly_ms;
  state.counters["factor_ms"] = stats.factorization_ms;
  state.counters["basis_ms"] = stats.basis_ms;
  state.counters["symmetric"] = stats.symmetric ? 1 : 0;
  state.counters["residual"] = stats.residual;
  state.counters["peak_rss_mb"] = peak_rss_mb();
  state.SetLabel(stats.solver);
}

void BM_BcmEvaluate(benchmark::State& state) {
  const int free_count = static_cast<int>(state.range(0)) * 1000;
  const int k = static_cast<int>(state.range(1));
  const bool blended = state.range(2) != 0;
  const EditSolver& solver = cached_solver(free_count, k, blended);
  VertexData<Vec3> out = bench_mesh().mesh.positions();
  const Vec3 pivot = solver.handle_centroid(0);
  int frame = 0;
  for (auto _ : state) {
    const double angle = 0.001 * (++frame % 100);
    const Eigen::Affine3d t = Eigen::Translation3d(pivot + Vec3(0, 0, angle)) *
                              Eigen::AngleAxisd(angle, Vec3::UnitX()) * Eigen::Translation3d(-pivot);
    solver.evaluate(std::span<const Eigen::Affine3d>(&t, 1), out);
    benchmark::DoNotOptimize(out.raw().data());
    benchmark::ClobberMemory();
  }
  state.counters["free"] = solver.regions().n_free();
}

// The peer (issue 13): the same basis product written plainly with Eigen, as a libigl user
// writes it (X = X0 + B * G with column-major dense B; bench/peer_product.cpp, -march=native),
// on our solver's basis.
void BM_EigenPlainEvaluate(benchmark::State& state) {
  const int free_count = static_cast<int>(state.range(0)) * 1000;
  const BcmSolver& bcm = cached_solver(free_count, 3, false).bcm();
  const Eigen::MatrixXd basis = bcm.basis();
  const Eigen::MatrixXd x0 = bcm.constant_part();
  Eigen::MatrixXd g(4, 3), x(basis.rows(), 3);
  int frame = 0;
  for (auto _ : state) {
    const double angle = 0.001 * (++frame % 100);
    const Eigen::Affine3d t(Eigen::AngleAxisd(angle, Vec3::UnitX()));
    for (int j = 0; j < 4; ++j) g.row(j) = (t * bcm.frame(0)[static_cast<std::size_t>(j)]).transpose();
    eigen_plain_product(x0.data(), basis.data(), g.data(), x.data(), basis.rows(), basis.cols());
    benchmark::DoNotOptimize(x.data());
    benchmark::ClobberMemory();
  }
  state.counters["free"] = static_cast<double>(basis.rows());
}

// Ours on the peer's terms: BcmSolver::evaluate into a P x 3 array (no scatter into the mesh).
void BM_BcmEvaluateRows(benchmark::State& state) {
  const int free_count = static_cast<int>(state.range(0)) * 1000;
  const BcmSolver& bcm = cached_solver(free_count, 3, false).bcm();
  BcmSolver::RowMatrixX3d x(bcm.n_free(), 3);
  int frame = 0;
  for (auto _ : state) {
    const double angle = 0.001 * (++frame % 100);
    const Eigen::Affine3d t(Eigen::AngleAxisd(angle, Vec3::UnitX()));
    bcm.evaluate(std::span<const Eigen::Affine3d>(&t, 1), x);
    benchmark::DoNotOptimize(x.data());
    benchmark::ClobberMemory();
  }
  state.counters["free"] = bcm.n_free();
}

// Precompute: every k at the small and middle sizes (3 repetitions up to 35k, 1 beyond), k = 3
// only at 140k and 300k.
void precompute_small(benchmark::internal::Benchmark* b) {
  for (int n : {10, 35}) {
    b->Args({n, 1, 0});
    for (int k : {2, 3}) b->Args({n, k, 0})->Args({n, k, 1});
  }
}
void precompute_large(benchmark::internal::Benchmark* b) {
  b->Args({100, 1, 0});
  for (int k : {2, 3}) b->Args({100, k, 0})->Args({100, k, 1});
  for (int n : {140, 300}) b->Args({n, 3, 0})->Args({n, 3, 1});
}
BENCHMARK(BM_BcmPrecompute)->Apply(precompute_small)->ArgNames({"kfree", "k", "blended"})->Iterations(1)
    ->Repetitions(3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BcmPrecompute)->Apply(precompute_large)->ArgNames({"kfree", "k", "blended"})->Iterations(1)
    ->Repetitions(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BcmEvaluate)->ArgsProduct({{10, 35, 100, 140, 300}, {3}, {0}})->ArgNames({"kfree", "k", "blended"})
    ->Unit(benchmark::kMicrosecond)->UseRealTime();
BENCHMARK(BM_BcmEvaluateRows)->Arg(35)->Arg(140)->Arg(300)->ArgNames({"kfree"})->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
BENCHMARK(BM_EigenPlainEvaluate)->Arg(35)->Arg(140)->Arg(300)->ArgNames({"kfree"})->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

#ifdef FREEFORM_HAVE_CGAL
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using SmVertex = SurfaceMesh::Vertex_index;

SurfaceMesh& cgal_mesh() {  // vertex i == soup vertex i
  static SurfaceMesh sm = [] {
    SurfaceMesh s;
    const BenchMesh& m = bench_mesh();
    for (const Vec3& p : m.soup.positions) s.add_vertex(Point(p.x(), p.y(), p.z()));
    for (const Tri& t : m.soup.faces)
      s.add_face(SmVertex(static_cast<SurfaceMesh::size_type>(t[0])), SmVertex(static_cast<SurfaceMesh::size_type>(t[1])),
                 SmVertex(static_cast<SurfaceMesh::size_type>(t[2])));
    return s;
  }();
  return sm;
}

void reset_positions(SurfaceMesh& sm, const std::vector<Vertex>& vertices) {
  const BenchMesh& m = bench_mesh();
  for (Vertex v : vertices) {
    const Vec3& p = m.mesh.position(v);
    sm.point(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx()))) = Point(p.x(), p.y(), p.z());
  }
}

// CGAL fair of the free vertices with fairing_continuity = k-1 (full smoothness), handle fixed.
void BM_CgalFair(benchmark::State& state) {
  const int free_count = static_cast<int>(state.range(0)) * 1000;
  const int k = static_cast<int>(state.range(1));
  const Region r = region(free_count);
  std::vector<Vertex> free;
  std::set_difference(r.support.begin(), r.support.end(), r.handle.begin(), r.handle.end(), std::back_inserter(free));
  std::vector<SmVertex> free_sm;
  for (Vertex v : free) free_sm.emplace_back(static_cast<SurfaceMesh::size_type>(v.idx()));
  SurfaceMesh& sm = cgal_mesh();
  for (auto _ : state) {
    const bool ok = CGAL::Polygon_mesh_processing::fair(
        sm, free_sm, CGAL::parameters::fairing_continuity(static_cast<unsigned>(k - 1)));
    if (!ok) state.SkipWithError("CGAL fair failed");
    state.PauseTiming();
    reset_positions(sm, free);
    state.ResumeTiming();
  }
  state.counters["free"] = static_cast<double>(free.size());
  state.counters["peak_rss_mb"] = peak_rss_mb();
}
BENCHMARK(BM_CgalFair)->Args({10, 1})->Args({10, 2})->Args({10, 3})->Args({35, 1})->Args({35, 2})->Args({35, 3})
    ->ArgNames({"kfree", "k"})->Iterations(1)->Repetitions(3)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CgalFair)->Args({100, 1})->Args({100, 2})->ArgNames({"kfree", "k"})->Iterations(1)->Repetitions(1)
    ->Unit(benchmark::kMillisecond)->UseRealTime();

using Deformation = CGAL::Surface_mesh_deformation<SurfaceMesh>;  // ARAP (spokes and rims)

std::unique_ptr<Deformation> make_deformation(SurfaceMesh& sm, const Region& r) {
  auto d = std::make_unique<Deformation>(sm);
  for (Vertex v : r.support) d->insert_roi_vertex(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx())));
  for (Vertex v : r.handle) d->insert_control_vertex(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx())));
  return d;
}

// ARAP precomputation: ROI and control vertices, then preprocess() (factorization).
void BM_CgalArapPreprocess(benchmark::State& state) {
  const Region r = region(static_cast<int>(state.range(0)) * 1000);
  SurfaceMesh& sm = cgal_mesh();
  for (auto _ : state) {
    auto d = make_deformation(sm, r);
    if (!d->preprocess()) state.SkipWithError("CGAL ARAP preprocess failed");
  }
  state.counters["peak_rss_mb"] = peak_rss_mb();
}
BENCHMARK(BM_CgalArapPreprocess)->Arg(10)->Arg(35)->ArgNames({"kfree"})->Iterations(1)->Repetitions(3)
    ->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_CgalArapPreprocess)->Arg(100)->Arg(300)->ArgNames({"kfree"})->Iterations(1)->Repetitions(1)
    ->Unit(benchmark::kMillisecond)->UseRealTime();

// One ARAP frame: move the control vertices, deform(1 iteration).
void BM_CgalArapFrame(benchmark::State& state) {
  const Region r = region(static_cast<int>(state.range(0)) * 1000);
  SurfaceMesh& sm = cgal_mesh();
  auto d = make_deformation(sm, r);
  if (!d->preprocess()) state.SkipWithError("CGAL ARAP preprocess failed");
  int frame = 0;
  for (auto _ : state) {
    const double lift = 0.001 * (++frame % 100);
    for (Vertex v : r.handle) {
      const Vec3 p = bench_mesh().mesh.position(v) + Vec3(0, 0, lift);
      d->set_target_position(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx())), Point(p.x(), p.y(), p.z()));
    }
    d->deform(1, 0.0);
  }
  d->reset();
  reset_positions(sm, r.support);
}
BENCHMARK(BM_CgalArapFrame)->Arg(10)->Arg(35)->Arg(100)->Arg(300)->ArgNames({"kfree"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();
#endif

}  // namespace

BENCHMARK_MAIN();
