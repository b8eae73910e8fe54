// Shared by the editor model tests.
#pragma once

#include "freeform/mesh/mesh.h"

#include <vector>

namespace freeform::editor::test_util {

// Vertices within xy-distance r of c (regions on the generated planes).
inline std::vector<Vertex> disc(const Mesh& m, Vec3 c, double r) {
  std::vector<Vertex> out;
  for (Vertex v : m.vertices())
    if ((m.position(v) - c).head<2>().norm() <= r) out.push_back(v);
  return out;
}

}  // namespace freeform::editor::test_util
