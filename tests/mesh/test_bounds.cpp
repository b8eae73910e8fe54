#include "freeform/mesh/bounds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace freeform {
namespace {

VertexData<Vec3> points(const std::vector<Vec3>& ps) {
  VertexData<Vec3> out(ps.size(), Vec3::Zero());
  for (std::size_t i = 0; i < ps.size(); ++i) out[Vertex(static_cast<int>(i))] = ps[i];
  return out;
}

TEST(BoundingDiagonal, IsTheBoxDiagonalOfTheFinitePositions) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_DOUBLE_EQ(bounding_diagonal(points({Vec3(0, 0, 0), Vec3(3, 4, 12), Vec3(1, 1, 1)})), 13.0);
  EXPECT_DOUBLE_EQ(bounding_diagonal(points({Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0), Vec3(3, 4, 0), Vec3(inf, 0, 0)})), 5.0);
}

TEST(BoundingDiagonal, IsOneWhenThereIsNoExtent) {
  EXPECT_EQ(bounding_diagonal(points({})), 1.0);
  EXPECT_EQ(bounding_diagonal(points({Vec3(2, 2, 2), Vec3(2, 2, 2)})), 1.0);
  EXPECT_EQ(bounding_diagonal(points({Vec3(-1e308, 0, 0), Vec3(1e308, 1e308, 0)})), 1.0);  // overflows
}

}  // namespace
}  // namespace freeform
