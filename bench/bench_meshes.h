// Shared by the benchmarks: where the libcgal-demo meshes are (large meshes come from them by
// subdivide_midpoint, mesh/generators.h).
#pragma once

#include "build_paths.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/traversal.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace freeform::bench {

inline std::filesystem::path mesh_dir() {
  const char* env = std::getenv("FREEFORM_MESH_DIR");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(build_paths::default_mesh_dir());
}

using freeform::subdivide_midpoint;  // mesh/generators.h

// bench_ordering's, bench_solve's and bench_assembly's support: the mesh subdivided `subdivisions` times and its
// first free_vertices + kScaleHandle vertices breadth-first from vertex 0, the first kScaleHandle
// of them the handle. nullopt when fewer vertices are reachable.
constexpr int kScaleHandle = 50;
struct ScaleSupport {
  Mesh mesh;
  std::vector<Vertex> support;
  std::vector<Vertex> handle() const { return {support.begin(), support.begin() + kScaleHandle}; }
};

inline std::optional<ScaleSupport> scale_support(const std::string& mesh_name, int subdivisions, int free_vertices) {
  TriangleSoup soup = read_mesh((mesh_dir() / mesh_name).string()).soup;
  for (int s = subdivisions; s > 0; --s) soup = subdivide_midpoint(soup);
  ScaleSupport out{Mesh::from_soup(soup), {}};
  const Vertex seed[] = {Vertex(0)};
  out.support = k_ring(out.mesh, seed, 1 << 20);
  if (static_cast<int>(out.support.size()) <= free_vertices + kScaleHandle) return std::nullopt;
  out.support.resize(static_cast<std::size_t>(free_vertices + kScaleHandle));
  return out;
}

// The same from a command line `mesh_name subdivisions free_in_thousands k ...`: exits 2 with
// `usage` when arguments are missing, 1 when too few vertices are reachable.
inline ScaleSupport scale_support_from_args(int argc, char** argv, const char* usage) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s\n", usage);
    std::exit(2);
  }
  std::optional<ScaleSupport> scene = scale_support(argv[1], std::stoi(argv[2]), std::stoi(argv[3]) * 1000);
  if (!scene) {
    std::fprintf(stderr, "too few vertices reachable from vertex 0\n");
    std::exit(1);
  }
  return std::move(*scene);
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace freeform::bench
