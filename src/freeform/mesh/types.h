// Basic geometric value types and the triangle soup (arrays as read from a file).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products on Vec3

#include <array>
#include <vector>

namespace freeform {

using Vec3 = Eigen::Vector3d;
using Tri = std::array<int, 3>;  // three 0-based vertex indices, counter-clockwise

// Vertex positions and triangles exactly as a file or generator produced them: no
// connectivity, no validation. Vertex order is the file order.
struct TriangleSoup {
  std::vector<Vec3> positions;
  std::vector<Tri> faces;
};

}  // namespace freeform
