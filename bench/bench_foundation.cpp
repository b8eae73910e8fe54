// Foundation benchmarks (issue 2): loading a 1M-vertex mesh (binary PLY, ascii OBJ) against
// CGAL's polygon-soup readers on the same files, halfedge connectivity build, and operator
// assembly at ~150k vertices. Run through scripts/bench.sh, which prints JSON with medians.
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/operators/operators.h"

#include <benchmark/benchmark.h>

#include <filesystem>
#include <map>

#ifdef FREEFORM_HAVE_CGAL
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>
#endif

namespace {

using namespace freeform;

// 1000 x 1000 vertex bumpy grid, written once per process to the temp folder.
const TriangleSoup& grid_1m() {
  static const TriangleSoup soup = make_bumpy_plane(999, 999, 0.05, 4.0);
  return soup;
}

std::string grid_file(const char* ext) {
  static std::map<std::string, std::string> files;
  auto it = files.find(ext);
  if (it != files.end()) return it->second;
  const auto path = std::filesystem::temp_directory_path() / (std::string("freeform-bench-grid-1m.") + ext);
  write_mesh(path.string(), grid_1m());
  return files[ext] = path.string();
}

void set_counters(benchmark::State& state, std::size_t vertices) {
  state.counters["vertices"] = static_cast<double>(vertices);
}

void BM_LoadBinaryPly1M(benchmark::State& state) {
  const std::string file = grid_file("ply");
  for (auto _ : state) benchmark::DoNotOptimize(read_mesh(file));
  set_counters(state, grid_1m().positions.size());
}

void BM_LoadObj1M(benchmark::State& state) {
  const std::string file = grid_file("obj");
  for (auto _ : state) benchmark::DoNotOptimize(read_mesh(file));
  set_counters(state, grid_1m().positions.size());
}

#ifdef FREEFORM_HAVE_CGAL
template <const char* Ext>
void BM_CgalLoad1M(benchmark::State& state) {
  using Point = CGAL::Simple_cartesian<double>::Point_3;
  const std::string file = grid_file(Ext);
  for (auto _ : state) {
    std::vector<Point> points;
    std::vector<std::vector<std::size_t>> faces;  // std::array faces crashed here (heap corruption) after CGAL 5.5's OBJ reader
    if (!CGAL::IO::read_polygon_soup(file, points, faces)) state.SkipWithError("CGAL could not read the file");
    benchmark::DoNotOptimize(points.data());
  }
  set_counters(state, grid_1m().positions.size());
}
constexpr char kPly[] = "ply";
constexpr char kObj[] = "obj";
BENCHMARK_TEMPLATE(BM_CgalLoad1M, kPly)->Name("BM_CgalLoadBinaryPly1M")->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(BM_CgalLoad1M, kObj)->Name("BM_CgalLoadObj1M")->Unit(benchmark::kMillisecond);
#endif

void BM_BuildConnectivity1M(benchmark::State& state) {
  const TriangleSoup& soup = grid_1m();
  for (auto _ : state) benchmark::DoNotOptimize(Mesh::from_soup(soup));
  set_counters(state, soup.positions.size());
}

// Icosphere with 6 subdivisions has 40962 vertices, 7 has 163842 (the ~150k case).
const Mesh& sphere(int subdivisions) {
  static std::map<int, Mesh> meshes;
  auto it = meshes.find(subdivisions);
  if (it == meshes.end()) it = meshes.emplace(subdivisions, Mesh::from_soup(make_icosphere(subdivisions))).first;
  return it->second;
}

void BM_CotanLaplacian(benchmark::State& state) {
  const Mesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(cotan_laplacian(m));
  set_counters(state, m.n_vertices());
}

void BM_MixedAreas(benchmark::State& state) {
  const Mesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(mixed_voronoi_areas(m));
  set_counters(state, m.n_vertices());
}

void BM_UniformLaplacian(benchmark::State& state) {
  const Mesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(uniform_laplacian(m));
  set_counters(state, m.n_vertices());
}

}  // namespace

BENCHMARK(BM_LoadBinaryPly1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadObj1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildConnectivity1M)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CotanLaplacian)->Arg(6)->Arg(7)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MixedAreas)->Arg(6)->Arg(7)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UniformLaplacian)->Arg(7)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
