// Shared by the benchmarks: where the libcgal-demo meshes are (large meshes come from them by
// subdivide_midpoint, mesh/generators.h).
#pragma once

#include "build_paths.h"
#include "freeform/mesh/generators.h"

#include <cstdlib>
#include <filesystem>

namespace freeform::bench {

inline std::filesystem::path mesh_dir() {
  const char* env = std::getenv("FREEFORM_MESH_DIR");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(build_paths::default_mesh_dir());
}

using freeform::subdivide_midpoint;  // mesh/generators.h

}  // namespace freeform::bench
