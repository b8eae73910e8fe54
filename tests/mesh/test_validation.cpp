#include "freeform/common/error.h"
#include "freeform/mesh/validation.h"
#include "mesh/mesh_fixtures.h"

#include <gtest/gtest.h>

using namespace freeform;
using namespace freeform::test;

TEST(Validation, CleanTetrahedronIsASphere) {
  const ValidationReport r = validate(tetrahedron());
  EXPECT_TRUE(r.manifold());
  EXPECT_TRUE(r.zero_area_faces.empty());
  EXPECT_TRUE(r.unreferenced_vertices.empty());
  EXPECT_TRUE(r.duplicate_vertices.empty());
  ASSERT_EQ(r.components.size(), 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.boundary_loops, 0);
}

TEST(Validation, TorusHasGenusOne) {
  const ValidationReport r = validate(torus(8, 6));
  EXPECT_TRUE(r.manifold());
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.genus, 1);
  EXPECT_EQ(r.boundary_loops, 0);
}

TEST(Validation, AnnulusHasTwoBoundaryLoops) {
  const ValidationReport r = validate(annulus_grid(3, 12));
  EXPECT_EQ(r.boundary_loops, 2);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.genus, 0);
}

TEST(Validation, ComponentsAreCountedSeparately) {
  TriangleSoup two = tetrahedron();
  const TriangleSoup t = torus(6, 5);
  const int offset = static_cast<int>(two.positions.size());
  two.positions.insert(two.positions.end(), t.positions.begin(), t.positions.end());
  for (Tri f : t.faces) two.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
  const ValidationReport r = validate(two);
  ASSERT_EQ(r.components.size(), 2u);
  EXPECT_EQ(r.components[0].genus, 0);
  EXPECT_EQ(r.components[1].genus, 1);
  EXPECT_EQ(r.components[1].faces, 60);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 1);
}

TEST(Validation, ReportsEveryDefectWithIndices) {
  TriangleSoup s = strip(6);                 // vertices 0..5, faces 0..3
  s.positions.push_back(s.positions[4]);     // 6: duplicate of 4, unreferenced
  s.positions.emplace_back(10, 10, 10);      // 7: unreferenced
  s.positions.emplace_back(0.25, 0.5, 0);    // 8: on the segment between 0 and 1 -> zero area
  s.faces.push_back({0, 8, 1});              // face 4: collinear
  s.faces.push_back({2, 2, 3});              // face 5: repeated index
  const ValidationReport r = validate(s);
  EXPECT_EQ(r.unreferenced_vertices, (std::vector<int>{6, 7}));
  ASSERT_EQ(r.duplicate_vertices.size(), 1u);
  EXPECT_EQ(r.duplicate_vertices[0], (std::array<int, 2>{4, 6}));
  EXPECT_EQ(r.zero_area_faces, (std::vector<int>{4}));
  EXPECT_EQ(r.repeated_index_faces, (std::vector<int>{5}));
  EXPECT_FALSE(r.manifold());
}

TEST(Validation, NegativeZeroIsTheSamePosition) {
  TriangleSoup s = tetrahedron();
  s.positions.emplace_back(-0.0, 0.0, -0.0);
  EXPECT_EQ(validate(s).duplicate_vertices.size(), 1u);
}

TEST(Validation, BowtieAndFinsAreNamed) {
  const TriangleSoup bowtie{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0, 2, 0), Vec3(1, 2, 0)},
                            {{0, 1, 2}, {2, 4, 3}}};
  ValidationReport r = validate(bowtie);
  EXPECT_EQ(r.nonmanifold_vertices, (std::vector<int>{2}));
  EXPECT_TRUE(r.nonmanifold_edges.empty());
  EXPECT_EQ(r.components.size(), 2u);  // after splitting, two triangles

  const TriangleSoup fins{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0), Vec3(0.5, 0, 1)},
                          {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
  r = validate(fins);
  ASSERT_EQ(r.nonmanifold_edges.size(), 1u);
  EXPECT_EQ(r.nonmanifold_edges[0], (std::array<int, 2>{0, 1}));

  const TriangleSoup flipped{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)}, {{0, 1, 2}, {0, 1, 3}}};
  r = validate(flipped);
  ASSERT_EQ(r.inconsistent_edges.size(), 1u);
  EXPECT_EQ(r.inconsistent_edges[0], (std::array<int, 2>{0, 1}));
}

TEST(Validation, OutOfRangeIsAnError) {
  TriangleSoup s = tetrahedron();
  s.faces.push_back({0, 1, 17});
  EXPECT_THROW(validate(s), InvalidInput);
}
