#include "freeform/common/error.h"
#include "freeform/mesh/mesh.h"
#include "mesh/mesh_fixtures.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

using namespace freeform;
using freeform::test::strip;
using freeform::test::tetrahedron;
using ::testing::HasSubstr;

namespace {

// Structural invariants every halfedge mesh must satisfy.
void expect_consistent(const Mesh& m) {
  for (Halfedge h : m.halfedges()) {
    EXPECT_EQ(m.opposite(m.opposite(h)), h);
    EXPECT_EQ(m.prev(m.next(h)), h);
    EXPECT_EQ(m.next(m.prev(h)), h);
    EXPECT_EQ(m.from_vertex(m.next(h)), m.to_vertex(h));
    EXPECT_NE(m.to_vertex(h), m.from_vertex(h));
    if (!m.is_boundary(h)) {
      EXPECT_EQ(m.next(m.next(m.next(h))), h);
      EXPECT_EQ(m.face(m.next(h)), m.face(h));
    }
  }
  for (Vertex v : m.vertices()) {
    if (m.is_isolated(v)) continue;
    EXPECT_EQ(m.from_vertex(m.halfedge(v)), v);
  }
  for (Face f : m.faces()) EXPECT_EQ(m.face(m.halfedge(f)), f);
}

}  // namespace

TEST(Mesh, TetrahedronCountsAndIncidence) {
  const TriangleSoup soup = tetrahedron();
  const Mesh m = Mesh::from_soup(soup);
  EXPECT_EQ(m.n_vertices(), 4);
  EXPECT_EQ(m.n_faces(), 4);
  EXPECT_EQ(m.n_edges(), 6);
  expect_consistent(m);
  for (Vertex v : m.vertices()) {
    EXPECT_EQ(m.valence(v), 3);
    EXPECT_FALSE(m.is_boundary(v));
  }
  // Faces keep their vertex order up to rotation and vertex i is soup vertex i.
  for (Face f : m.faces()) {
    auto v = m.vertices(f);
    const Tri& t = soup.faces[f.idx()];
    std::array<int, 3> got{v[0].idx(), v[1].idx(), v[2].idx()};
    std::rotate(got.begin(), std::find(got.begin(), got.end(), t[0]), got.end());
    EXPECT_EQ(got, t);
  }
  EXPECT_EQ(m.position(Vertex(3)), Vec3(0, 0, 1));
}

TEST(Mesh, SingleTriangleHasBoundaryLoopOfThree) {
  const Mesh m = Mesh::from_soup({{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}}});
  expect_consistent(m);
  int boundary = 0;
  for (Halfedge h : m.halfedges())
    if (m.is_boundary(h)) {
      ++boundary;
      EXPECT_EQ(m.next(m.next(m.next(h))), h);
    }
  EXPECT_EQ(boundary, 3);
  for (Vertex v : m.vertices()) EXPECT_TRUE(m.is_boundary(v));
}

TEST(Mesh, CirculationAroundBoundaryVertexVisitsWholeFan) {
  const Mesh m = Mesh::from_soup(strip(7));
  expect_consistent(m);
  std::set<int> ring;
  for (Halfedge h : m.outgoing(Vertex(3))) ring.insert(m.to_vertex(h).idx());
  EXPECT_EQ(ring, (std::set<int>{1, 2, 4, 5}));
  EXPECT_EQ(m.valence(Vertex(0)), 2);
  EXPECT_TRUE(m.find_halfedge(Vertex(2), Vertex(4)).is_valid());
  EXPECT_FALSE(m.find_halfedge(Vertex(0), Vertex(3)).is_valid());
}

TEST(Mesh, SoupRoundTripAndPositionMatrix) {
  const TriangleSoup soup = freeform::test::torus(5, 4);
  Mesh m = Mesh::from_soup(soup);
  const TriangleSoup back = m.to_soup();
  EXPECT_EQ(back.positions, soup.positions);
  ASSERT_EQ(back.faces.size(), soup.faces.size());
  Eigen::MatrixX3d x = m.position_matrix();
  x.col(2).array() += 1.0;
  m.set_positions(x);
  EXPECT_DOUBLE_EQ(m.position(Vertex(7)).z(), soup.positions[7].z() + 1.0);
  EXPECT_THROW(m.set_positions(Eigen::MatrixX3d(3, 3)), InvalidInput);
}

TEST(Mesh, IsolatedVertexKeepsItsIndex) {
  const Mesh m = Mesh::from_soup({{Vec3(0, 0, 0), Vec3(9, 9, 9), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 2, 3}}});
  EXPECT_EQ(m.n_vertices(), 4);
  EXPECT_TRUE(m.is_isolated(Vertex(1)));
  EXPECT_EQ(m.valence(Vertex(1)), 0);
  int count = 0;
  for ([[maybe_unused]] Halfedge h : m.outgoing(Vertex(1))) ++count;
  EXPECT_EQ(count, 0);
}

TEST(Mesh, BowtieIsRefusedNamingTheVertex) {
  // Two triangles touching only at vertex 2.
  const TriangleSoup bowtie{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0, 2, 0), Vec3(1, 2, 0)},
                            {{0, 1, 2}, {2, 4, 3}}};
  try {
    Mesh::from_soup(bowtie);
    FAIL() << "bowtie accepted";
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), HasSubstr("(2, 2)"));  // vertex 2 has 2 fans
    EXPECT_THAT(e.what(), HasSubstr("repair"));
  }
  BuildReport report;
  const Mesh m = Mesh::from_soup(bowtie, {.repair = true}, &report);
  expect_consistent(m);
  EXPECT_EQ(m.n_vertices(), 6);
  EXPECT_EQ(report.split_vertices, 1);
  EXPECT_EQ(report.added_vertices, 1);
  ASSERT_EQ(report.origin.size(), 1u);
  EXPECT_EQ(report.origin[0], 2);
  EXPECT_EQ(m.position(Vertex(5)), m.position(Vertex(2)));
  ASSERT_EQ(report.changes.size(), 1u);
  EXPECT_THAT(report.changes[0], HasSubstr("split vertex 2"));
}

TEST(Mesh, NonManifoldEdgeIsRefusedOrSplit) {
  // Three fins on edge (0, 1).
  const TriangleSoup fins{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0), Vec3(0.5, 0, 1)},
                          {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}};
  try {
    Mesh::from_soup(fins);
    FAIL() << "non-manifold edge accepted";
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), HasSubstr("non-manifold edges (0, 1)"));
  }
  BuildReport report;
  const Mesh m = Mesh::from_soup(fins, {.repair = true}, &report);
  expect_consistent(m);
  EXPECT_EQ(report.split_vertices, 2);
  EXPECT_EQ(report.added_vertices, 4);  // 0 and 1 each become three
  EXPECT_EQ(m.n_vertices(), 9);
  EXPECT_EQ(m.n_edges(), 9);  // nothing glued any more
}

TEST(Mesh, InconsistentOrientationIsRefused) {
  const TriangleSoup soup{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1, 0), Vec3(0.5, -1, 0)}, {{0, 1, 2}, {0, 1, 3}}};
  try {
    Mesh::from_soup(soup);
    FAIL() << "inconsistent orientation accepted";
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), HasSubstr("inconsistently oriented faces across edges (0, 1)"));
  }
  const Mesh m = Mesh::from_soup(soup, {.repair = true});
  expect_consistent(m);
  EXPECT_EQ(m.n_vertices(), 6);
}

TEST(Mesh, RepeatedIndexFaceIsRefusedOrDropped) {
  const TriangleSoup soup{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)}, {{0, 1, 2}, {1, 1, 2}}};
  try {
    Mesh::from_soup(soup);
    FAIL();
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), HasSubstr("face 1 (1, 1, 2) repeats a vertex"));
  }
  BuildReport report;
  const Mesh m = Mesh::from_soup(soup, {.repair = true}, &report);
  EXPECT_EQ(m.n_faces(), 1);
  EXPECT_EQ(report.dropped_faces, 1);
}

TEST(Mesh, BadIndicesAndCoordinatesAreInvalidInput) {
  TriangleSoup soup = tetrahedron();
  soup.faces[2][1] = 4;
  EXPECT_THROW(
      {
        try {
          Mesh::from_soup(soup);
        } catch (const InvalidInput& e) {
          EXPECT_THAT(e.what(), HasSubstr("face 2 references vertex 4"));
          throw;
        }
      },
      InvalidInput);
  soup = tetrahedron();
  soup.faces[0][0] = -1;
  EXPECT_THROW(Mesh::from_soup(soup), InvalidInput);
  soup = tetrahedron();
  soup.positions[1].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(Mesh::from_soup(soup), InvalidInput);
}
