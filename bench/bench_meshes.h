// Shared by the benchmarks: where the libcgal-demo meshes are and a midpoint subdivision to
// make large meshes from them.
#pragma once

#include "freeform/mesh/types.h"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <unordered_map>

namespace freeform::bench {

inline std::filesystem::path mesh_dir() {
  const char* env = std::getenv("FREEFORM_MESH_DIR");
  return env && *env ? std::filesystem::path(env) : std::filesystem::path(FREEFORM_DEFAULT_MESH_DIR);
}

// Each triangle into four through its edge midpoints (positions not smoothed).
inline TriangleSoup subdivide_midpoint(const TriangleSoup& in) {
  TriangleSoup out;
  out.positions = in.positions;
  out.faces.reserve(in.faces.size() * 4);
  std::unordered_map<std::uint64_t, int> midpoint;
  midpoint.reserve(in.faces.size() * 2);
  auto mid = [&](int a, int b) {
    const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
    auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(out.positions.size()));
    if (inserted) out.positions.push_back(0.5 * (in.positions[static_cast<std::size_t>(a)] + in.positions[static_cast<std::size_t>(b)]));
    return it->second;
  };
  for (const Tri& t : in.faces) {
    const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
    out.faces.push_back({t[0], ab, ca});
    out.faces.push_back({t[1], bc, ab});
    out.faces.push_back({t[2], ca, bc});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

}  // namespace freeform::bench
