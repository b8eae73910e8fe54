// Vertex selectors and the Botsch-Sorkine .sel/.def files, against hand-computed facts.
#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/sel_file.h"
#include "freeform/regions/selectors.h"
#include "test_support.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

using namespace freeform;
using ::testing::HasSubstr;

namespace {

// Message of the exception `f` throws (type E), or "" if it throws nothing.
template <class E, class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

Mesh unit_grid(int n) { return Mesh::from_soup(make_plane(n, n)); }  // spacing 1/n

}  // namespace

TEST(Selectors, IndicesAreSortedUniqueAndChecked) {
  const Mesh mesh = unit_grid(4);  // 25 vertices
  const std::vector<long long> ids = {7, 3, 7, 0};
  EXPECT_EQ(select_indices(mesh, ids, "sel"), (std::vector<Vertex>{Vertex(0), Vertex(3), Vertex(7)}));
  const std::vector<long long> bad = {1, 25};
  EXPECT_THAT(error_of<InvalidInput>([&] { select_indices(mesh, bad, "handles[0].region"); }),
              HasSubstr("handles[0].region: vertex index 25 (entry 1) is outside the mesh"));
  const std::vector<long long> negative = {-1};
  EXPECT_THAT(error_of<InvalidInput>([&] { select_indices(mesh, negative, "support"); }), HasSubstr("index -1"));
  EXPECT_THAT(error_of<InvalidInput>([&] { select_indices(mesh, {}, "support"); }),
              HasSubstr("support selects no vertex"));
}

TEST(Selectors, SphereOnAGridCountsLatticePoints) {
  const Mesh mesh = unit_grid(10);
  // Integer points with x^2 + y^2 <= 2.5^2: 5 + 2*5 + 2*3 = 21.
  EXPECT_EQ(select_sphere(mesh, Vec3(0.5, 0.5, 0.0), 0.25, "s").size(), 21u);
  // 0.2 above the plane, radius 0.25 -> a disk of radius 0.15 = 1.5 spacings: 3 + 2*3 = 9.
  EXPECT_EQ(select_sphere(mesh, Vec3(0.5, 0.5, 0.2), 0.25, "s").size(), 9u);
  // The corner: a quarter disk of radius 2.5 spacings -> (x, y >= 0): 3 + 3 + 2 = 8.
  EXPECT_EQ(select_sphere(mesh, Vec3(0, 0, 0), 0.25, "s").size(), 8u);
  EXPECT_THAT(error_of<InvalidInput>([&] { select_sphere(mesh, Vec3(5, 5, 5), 0.1, "support"); }),
              HasSubstr("support selects no vertex"));
  EXPECT_THAT(error_of<InvalidInput>([&] { select_sphere(mesh, Vec3(0, 0, 0), -1.0, "support"); }),
              HasSubstr("radius"));
  EXPECT_THAT(error_of<InvalidInput>([&] { select_sphere(mesh, Vec3(NAN, 0, 0), 1.0, "support"); }),
              HasSubstr("center"));
}

TEST(Selectors, NearestVertex) {
  const Mesh mesh = unit_grid(10);
  EXPECT_EQ(nearest_vertex(mesh, Vec3(0.31, 0.58, 0.4)), Vertex(6 * 11 + 3));
  EXPECT_EQ(nearest_vertex(mesh, Vec3(-3, -3, 0)), Vertex(0));
}

TEST(Selectors, GeodesicOnAPlaneIsEuclideanUpToEdgePaths) {
  const int n = 20;
  const Mesh mesh = unit_grid(n);
  const Vertex c = nearest_vertex(mesh, Vec3(0.5, 0.5, 0));
  const VertexData<double> d = geodesic_distance(mesh, c);
  double worst = 1.0;
  for (Vertex v : mesh.vertices()) {
    const double e = (mesh.position(v) - mesh.position(c)).norm();
    ASSERT_GE(d[v], e - 1e-12);  // an edge path is never shorter than the straight line
    if (e > 0) worst = std::max(worst, d[v] / e);
    // Along grid lines the edge path is the straight line.
    if (std::abs(mesh.position(v).y() - 0.5) < 1e-12) {
      EXPECT_NEAR(d[v], e, 1e-12);
    }
  }
  // 8-neighbour-like paths: at most ~8% longer (alternating diagonals give slightly more).
  EXPECT_LT(worst, 1.1);
  // So a geodesic disk lies between the Euclidean disks of radius r/1.1 and r.
  const double r = 0.3;
  const auto geo = select_geodesic(mesh, Vec3(0.5, 0.5, 0), r, "g");
  const auto outer = select_sphere(mesh, Vec3(0.5, 0.5, 0), r, "s");
  const auto inner = select_sphere(mesh, Vec3(0.5, 0.5, 0), r / 1.1, "s");
  EXPECT_LE(geo.size(), outer.size());
  EXPECT_GE(geo.size(), inner.size());
  for (Vertex v : inner) EXPECT_TRUE(std::binary_search(geo.begin(), geo.end(), v));
}

TEST(Selectors, GeodesicOnACylinderFollowsTheSurface) {
  const int segments = 32;
  const double radius = 1.0;
  const Mesh mesh = Mesh::from_soup(make_cylinder(4, segments, radius, 1.0));
  const Vertex a = nearest_vertex(mesh, Vec3(radius, 0, 0.5));
  const Vertex b = nearest_vertex(mesh, Vec3(-radius, 0, 0.5));
  const double chord = (mesh.position(a) - mesh.position(b)).norm();
  EXPECT_NEAR(chord, 2 * radius, 1e-12);
  // Half the inscribed polygon's perimeter, about pi * r.
  const double around = segments / 2 * 2 * radius * std::sin(std::numbers::pi / segments);
  EXPECT_NEAR(geodesic_distance(mesh, a)[b], around, 1e-9);
  // A radius between the chord and the surface distance: the sphere reaches b, the geodesic
  // disk does not.
  const auto sphere = select_sphere(mesh, mesh.position(a), 2.5, "s");
  const auto geo = select_geodesic(mesh, mesh.position(a), 2.5, "g");
  EXPECT_TRUE(std::binary_search(sphere.begin(), sphere.end(), b));
  EXPECT_FALSE(std::binary_search(geo.begin(), geo.end(), b));
  EXPECT_LT(geo.size(), sphere.size());
}

TEST(Selectors, GeodesicDistanceStopsAtMaxDistance) {
  const Mesh mesh = unit_grid(10);
  const VertexData<double> d = geodesic_distance(mesh, Vertex(0), 0.25);
  EXPECT_NEAR(d[Vertex(2)], 0.2, 1e-12);
  EXPECT_TRUE(std::isinf(d[Vertex(5)]));
}

// The positions overload measures the given shape (the editor's flood on a deformed mesh):
// stretching the grid by 3 along x triples the distances along the x grid line, and `reached`
// lists exactly the vertices with a finite distance, nearest first.
TEST(Selectors, GeodesicDistanceOnOtherPositions) {
  const Mesh mesh = unit_grid(10);
  VertexData<Vec3> stretched = mesh.positions();
  for (Vec3& p : stretched.raw()) p.x() *= 3.0;
  std::vector<Vertex> reached;
  const VertexData<double> d = geodesic_distance(mesh, stretched, Vertex(0), 0.65, &reached);
  EXPECT_NEAR(d[Vertex(2)], 0.6, 1e-12);  // (0.2, 0) stretched to (0.6, 0)
  EXPECT_TRUE(std::isinf(d[Vertex(3)]));  // 0.9 > 0.65
  EXPECT_NEAR(d[Vertex(11 * 6)], 0.6, 1e-12);  // (0, 0.6): not stretched
  int finite = 0;
  for (Vertex v : mesh.vertices()) finite += std::isfinite(d[v]) ? 1 : 0;
  EXPECT_EQ(static_cast<int>(reached.size()), finite);
  for (std::size_t i = 1; i < reached.size(); ++i) EXPECT_LE(d[reached[i - 1]], d[reached[i]]);
  EXPECT_THROW((void)geodesic_distance(mesh, VertexData<Vec3>(3, Vec3::Zero()), Vertex(0), 1.0), InvalidInput);
}

TEST(Selectors, Labels) {
  const std::vector<int> labels = {0, 1, 2, 1, 0};
  const int free_and_handle[] = {1, 2};
  EXPECT_EQ(select_labels(labels, free_and_handle, "l"), (std::vector<Vertex>{Vertex(1), Vertex(2), Vertex(3)}));
  const std::vector<int> no_handle = {0, 1, 1};
  const int handle[] = {2};
  EXPECT_THAT(error_of<InvalidInput>([&] { select_labels(no_handle, handle, "handles[0].region"); }),
              HasSubstr("handles[0].region selects no vertex (no vertex has label 2)"));
}

TEST(SelFile, ParsesCommentsAndLabels) {
  const auto labels = parse_sel("# a comment\n#another\n0\n1\r\n2\n\n  1  \n", "x.sel", 4);
  EXPECT_EQ(labels, (std::vector<int>{0, 1, 2, 1}));
}

TEST(SelFile, ErrorsNameFileAndLine) {
  EXPECT_THAT(error_of<IoError>([] { parse_sel("#c\n0\n1\n", "a.sel", 3); }),
              HasSubstr("a.sel:3: the file ends after 2 labels, but the mesh has 3 vertices"));
  EXPECT_THAT(error_of<IoError>([] { parse_sel("#c\n0\n1\n2\n", "a.sel", 2); }),
              HasSubstr("a.sel:4: more labels than the mesh's 2 vertices"));
  EXPECT_THAT(error_of<IoError>([] { parse_sel("#c\n0\n3\n", "a.sel", 2); }), HasSubstr("a.sel:3: label \"3\""));
  EXPECT_THAT(error_of<IoError>([] { parse_sel("0\nx\n", "a.sel", 2); }), HasSubstr("a.sel:2: label \"x\""));
  EXPECT_THAT(error_of<IoError>([] { parse_sel("0 1\n", "a.sel", 2); }), HasSubstr("a.sel:1: expected one label"));
  EXPECT_THAT(error_of<IoError>([] { read_sel_file("/no/such/file.sel", 2); }), HasSubstr("/no/such/file.sel"));
}

TEST(DefFile, ParsesTheMatrixRowMajor) {
  const Eigen::Matrix4d m = parse_def("# handle transform\n1 0 0 0.5\n0 1 0 0\n0 0 1 -2\n0 0 0 1\n", "a.def");
  EXPECT_EQ(m(0, 3), 0.5);
  EXPECT_EQ(m(2, 3), -2.0);
  EXPECT_EQ(m(3, 3), 1.0);
  // A non-numeric first line is the comment line too; numbers may wrap freely.
  const Eigen::Matrix4d w = parse_def("transformation\n1 0 0 0 0 1 0 0\n0 0 1 3 0 0 0 1", "b.def");
  EXPECT_EQ(w(2, 3), 3.0);
}

TEST(DefFile, ErrorsNameFileAndLine) {
  EXPECT_THAT(error_of<IoError>([] { parse_def("#c\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0\n", "a.def"); }),
              HasSubstr("a.def:5: the file ends after 15 numbers"));
  EXPECT_THAT(error_of<IoError>([] { parse_def("#c\n1 0 0 0\n0 1 zero 0\n", "a.def"); }),
              HasSubstr("a.def:3: expected a finite number of the 4x4 matrix, found \"zero\""));
  EXPECT_THAT(error_of<IoError>([] { parse_def("#c\n1 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1 7\n", "a.def"); }),
              HasSubstr("a.def:5: more than 16 numbers"));
  EXPECT_THAT(error_of<IoError>([] { parse_def("#c\n1 0 0 nan\n", "a.def"); }), HasSubstr("a.def:2"));
}
