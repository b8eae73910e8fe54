#include "freeform/mesh/traversal.h"
#include "mesh/mesh_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace freeform;
using namespace freeform::test;

TEST(Traversal, OneRingIsInRotationOrder) {
  // Fan of 6 triangles around vertex 0: neighbours in rotation order are consecutive.
  TriangleSoup fan;
  fan.positions.emplace_back(0, 0, 0);
  for (int k = 0; k < 6; ++k) fan.positions.emplace_back(std::cos(k * M_PI / 3), std::sin(k * M_PI / 3), 0);
  for (int k = 0; k < 6; ++k) fan.faces.push_back({0, 1 + k, 1 + (k + 1) % 6});
  const Mesh m = Mesh::from_soup(fan);
  const auto ring = one_ring(m, Vertex(0));
  ASSERT_EQ(ring.size(), 6u);
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const int a = ring[i].idx() - 1, b = ring[(i + 1) % ring.size()].idx() - 1;
    EXPECT_TRUE((a + 1) % 6 == b || (b + 1) % 6 == a) << "not adjacent: " << a << " " << b;
  }
}

TEST(Traversal, RingDistanceOnStripIsHalfTheIndexGap) {
  const Mesh m = Mesh::from_soup(strip(12));
  const Vertex seed(0);
  const VertexData<int> d = ring_distance(m, std::span(&seed, 1), 100);
  for (Vertex v : m.vertices()) EXPECT_EQ(d[v], (v.idx() + 1) / 2) << v.idx();
  const VertexData<int> capped = ring_distance(m, std::span(&seed, 1), 2);
  EXPECT_EQ(capped[Vertex(4)], 2);
  EXPECT_EQ(capped[Vertex(5)], -1);
}

TEST(Traversal, KRingFromSeveralSeeds) {
  const Mesh m = Mesh::from_soup(strip(20));
  const std::vector<Vertex> seeds{Vertex(0), Vertex(19)};
  auto ring = k_ring(m, seeds, 1);
  std::vector<int> ids;
  for (Vertex v : ring) ids.push_back(v.idx());
  std::sort(ids.begin(), ids.end());
  EXPECT_EQ(ids, (std::vector<int>{0, 1, 2, 17, 18, 19}));
  EXPECT_EQ(ring.front().idx(), 0);  // seeds first
  EXPECT_EQ(k_ring(m, seeds, 0).size(), 2u);
}

TEST(Traversal, BoundaryLoopsOfAnnulus) {
  const Mesh m = Mesh::from_soup(annulus_grid(3, 10));
  const auto loops = boundary_loops(m);
  ASSERT_EQ(loops.size(), 2u);
  for (const auto& loop : loops) {
    EXPECT_EQ(loop.size(), 10u);
    for (std::size_t i = 0; i < loop.size(); ++i) EXPECT_EQ(m.next(loop[i]), loop[(i + 1) % loop.size()]);
  }
  EXPECT_TRUE(boundary_loops(Mesh::from_soup(torus(5, 5))).empty());
}

TEST(Traversal, ComponentsIncludeIsolatedVertices) {
  TriangleSoup s = strip(5);
  s.positions.emplace_back(7, 7, 7);
  const Mesh m = Mesh::from_soup(s);
  const Components c = connected_components(m);
  EXPECT_EQ(c.count, 2);
  EXPECT_EQ(c.vertex_component[Vertex(5)], 1);
  for (Face f : m.faces()) EXPECT_EQ(c.face_component[f], 0);
}

TEST(Traversal, BreadthFirstOrderVisitsRingByRing) {
  const Mesh m = Mesh::from_soup(torus(8, 8));
  std::vector<Vertex> set;
  for (int i = m.n_vertices() - 1; i >= 0; --i) set.push_back(Vertex(i));
  const std::vector<Vertex> order = breadth_first_order(m, set);
  ASSERT_EQ(order.size(), set.size());
  EXPECT_EQ(order.front(), set.front());
  std::vector<Vertex> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end()) << "a vertex twice";
  const VertexData<int> d = ring_distance(m, std::span(&order.front(), 1), 100);
  for (std::size_t i = 1; i < order.size(); ++i) EXPECT_LE(d[order[i - 1]], d[order[i]]) << i;
  EXPECT_GT(d[order.back()], 1);  // the test can fail: the torus has more than two rings
}

TEST(Traversal, BreadthFirstOrderKeepsPiecesApartInTheOrderOfTheirFirstVertex) {
  const Mesh m = Mesh::from_soup(strip(20));
  const std::vector<Vertex> set{Vertex(16), Vertex(15), Vertex(17), Vertex(3), Vertex(2), Vertex(4)};
  std::vector<int> starts{7};  // replaced
  const std::vector<Vertex> order = breadth_first_order(m, set, &starts);
  ASSERT_EQ(order.size(), 6u);
  EXPECT_EQ(starts, (std::vector<int>{0, 3}));
  EXPECT_EQ(order[0], Vertex(16));
  EXPECT_EQ(order[3], Vertex(3));
  std::vector<int> first, second;
  for (int i = 0; i < 3; ++i) first.push_back(order[static_cast<std::size_t>(i)].idx());
  for (int i = 3; i < 6; ++i) second.push_back(order[static_cast<std::size_t>(i)].idx());
  std::sort(first.begin(), first.end());
  std::sort(second.begin(), second.end());
  EXPECT_EQ(first, (std::vector<int>{15, 16, 17}));
  EXPECT_EQ(second, (std::vector<int>{2, 3, 4}));
}
