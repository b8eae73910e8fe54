// Reading every supported variant of OBJ, OFF, PLY and STL.
#include "io_test_util.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

namespace freeform::test {
namespace {

using ::testing::HasSubstr;

TEST(ReadObj, TetraWithAllSlashFormsAndIgnoredStatements) {
  const ReadResult r = read_mesh(tiny("tetra.obj"));
  expect_same(r.soup, tetra());
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadObj, QuadsNegativeIndicesAndLineContinuation) {
  const ReadResult r = read_mesh(tiny("quad_mix.obj"));
  ASSERT_EQ(r.soup.positions.size(), 6u);
  const std::vector<Tri> expected = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}, {0, 1, 2}, {3, 4, 5}};
  EXPECT_EQ(r.soup.faces, expected);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_THAT(r.warnings[0], HasSubstr("2 polygons"));
  EXPECT_THAT(r.warnings[0], HasSubstr("4 triangles"));
}

TEST(ReadObj, ForwardReferencesCrlfAndInlineComments) {
  const std::string data = "f 1 2 3 # comment\r\nv 0 0 0\r\nv +1 0 0\r\nv 0 1e0 0\r\n";
  const TriangleSoup s = read_mem(MeshFormat::Obj, data, "fwd.obj");
  ASSERT_EQ(s.positions.size(), 3u);
  EXPECT_EQ(s.positions[2], Vec3(0, 1, 0));
  EXPECT_EQ(s.faces, (std::vector<Tri>{{0, 1, 2}}));
}

TEST(ReadOff, CubeQuadsAreFanTriangulatedWithOneWarning) {
  const ReadResult r = read_mesh(tiny("cube.off"));
  EXPECT_EQ(r.soup.positions.size(), 8u);
  EXPECT_EQ(r.soup.faces.size(), 12u);
  EXPECT_EQ(r.soup.positions[6], Vec3(1, 1, 1));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_THAT(r.warnings[0], HasSubstr("6 polygons"));
}

// The triangles of faces [first, first + count): each with the polygon's orientation (+z), their
// areas' sum (they tile the polygon when it equals the polygon's own), and per vertex how many
// use it.
double tiled_area(const TriangleSoup& soup, int first, int count, std::vector<int>& uses) {
  double area = 0.0;
  for (int t = first; t < first + count; ++t) {
    const Tri& f = soup.faces[static_cast<std::size_t>(t)];
    const Vec3 normal =
        (soup.positions[f[1]] - soup.positions[f[0]]).cross(soup.positions[f[2]] - soup.positions[f[0]]);
    EXPECT_GT(normal.z(), 0.0) << "triangle " << t;
    area += 0.5 * normal.z();
    for (int v : f) ++uses[static_cast<std::size_t>(v)];
  }
  return area;
}

// A convex polygon of many corners (a CAD disc, a cylinder's cap) is cut into a strip, not a fan
// that would give its first corner 1,021 triangles: the strip's triangles tile it, with its
// orientation, no corner in more than four. A twelve-pointed star is cut by ear clipping (its fan
// from a tip overlaps itself: triangles of both orientations); a hexagon keeps the fan. OBJ and
// OFF alike.
TEST(ReadObj, LargeConvexPolygonsAreCutIntoStripsAndNonConvexOnesByEarClipping) {
  constexpr int n = 1024;
  std::ostringstream vertices;
  vertices.precision(17);
  const auto ring = [&](int count, double inner, double z) {
    for (int i = 0; i < count; ++i) {
      const double a = 2.0 * std::numbers::pi * i / count, r = i % 2 == 1 ? inner : 1.0;
      vertices << "v " << r * std::cos(a) << " " << r * std::sin(a) << " " << z << "\n";
    }
  };
  ring(n, 1.0, 0.0);   // vertices 1 .. n: the disc
  ring(6, 1.0, 1.0);   // a hexagon
  ring(12, 0.5, 2.0);  // a twelve-pointed star
  std::string disc = "f", hexagon = "f", star = "f";
  for (int i = 1; i <= n; ++i) disc += " " + std::to_string(i);
  for (int i = 1; i <= 6; ++i) hexagon += " " + std::to_string(n + i);
  for (int i = 1; i <= 12; ++i) star += " " + std::to_string(n + 6 + i);
  const std::string obj = vertices.str() + disc + "\n" + hexagon + "\n" + star + "\n";
  const ReadResult r = read_file_mem(MeshFormat::Obj, obj, "disc.obj");
  ASSERT_EQ(r.soup.faces.size(), std::size_t{n - 2 + 4 + 10});
  std::vector<int> uses(r.soup.positions.size(), 0);
  EXPECT_NEAR(tiled_area(r.soup, 0, n - 2, uses), 0.5 * n * std::sin(2.0 * std::numbers::pi / n), 1e-12);
  EXPECT_LE(*std::max_element(uses.begin(), uses.begin() + n), 4);
  for (int i = 1; i < 5; ++i) EXPECT_EQ(r.soup.faces[n - 3 + i], (Tri{n, n + i, n + i + 1}));
  // The star: 12 triangles of (1 * 0.5 * sin 30 deg) / 2 around its centre.
  EXPECT_NEAR(tiled_area(r.soup, n + 2, 10, uses), 12 * 0.25 * std::sin(std::numbers::pi / 6), 1e-12);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0],
            "3 polygons with more than 3 vertices triangulated into 1036 triangles (1 convex one of "
            "more than 8 corners cut into strips, 1 non-convex one by ear clipping, the others fanned)");
  std::ostringstream off_vertices;
  off_vertices.precision(17);
  for (const Vec3& p : r.soup.positions) off_vertices << p.x() << " " << p.y() << " " << p.z() << "\n";
  std::string off = "OFF\n" + std::to_string(n + 18) + " 3 0\n" + off_vertices.str();
  for (const auto& [first, count] : {std::pair{0, n}, std::pair{n, 6}, std::pair{n + 6, 12}}) {
    off += std::to_string(count);
    for (int i = 0; i < count; ++i) off += " " + std::to_string(first + i);
    off += "\n";
  }
  EXPECT_EQ(read_file_mem(MeshFormat::Off, off, "disc.off").soup.faces, r.soup.faces);
}

TEST(ReadOff, ColoredWithCountsOnHeaderLine) {
  const ReadResult r = read_mesh(tiny("colored.off"));
  expect_same(r.soup, tetra());
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadOff, HeaderVariants) {
  const std::string faces = "3 0 1 2\n";
  struct Case {
    std::string text;
    Vec3 second;
  };
  const std::vector<Case> cases = {
      {"NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n" + faces, Vec3(1, 0, 0)},
      {"CNOFF 3 1 0\n0 0 0 0 0 1 1 0 0 1\n2 0 0 0 0 1 1 0 0 1\n0 1 0 0 0 1 1 0 0 1\n" + faces, Vec3(2, 0, 0)},
      {"STOFF\n# comment\n\n3 1\n0 0 0 0.5 0.5\n3 0 0 1 1 # uv\n0 1 0 0 0\n" + faces, Vec3(3, 0, 0)},
      {"4OFF\n3 1 0\n0 0 0 1\n2 4 6 2\n0 1 0 1\n" + faces, Vec3(1, 2, 3)},
      {"nOFF\n3\n3 1 0\n0 0 0\n5 0 0\n0 1 0\n" + faces, Vec3(5, 0, 0)},
      {"\xEF\xBB\xBFOFF\r\n3 1 0\r\n0 0 0\r\n6 0 0\r\n0 1 0\r\n3 0 1 2\r\n", Vec3(6, 0, 0)},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const TriangleSoup s = read_mem(MeshFormat::Off, c.text, "v.off");
    ASSERT_EQ(s.positions.size(), 3u);
    EXPECT_EQ(s.positions[1], c.second);
    EXPECT_EQ(s.faces, (std::vector<Tri>{{0, 1, 2}}));
  }
}

TEST(ReadPly, AsciiWithExtraPropertiesAndElements) {
  const ReadResult r = read_mesh(tiny("tetra_ascii.ply"));
  expect_same(r.soup, tetra());
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadPly, BigEndianFileWithExtraElement) {
  const ReadResult r = read_mesh(tiny("tetra_be.ply"));
  expect_same(r.soup, tetra());
  EXPECT_TRUE(r.warnings.empty());
}

// A binary tetrahedron with the given types, plus an extra property, a per-face list and an
// extra element with a list, in either byte order.
struct PlyTypes {
  std::string coord, count, index, index_name;
};

template <class C, class N, class I>
std::string binary_tetra(const PlyTypes& t, bool big) {
  std::string header =
      std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
      " 1.0\nelement vertex 4\nproperty " + t.coord + " x\nproperty uchar tag\nproperty " + t.coord + " y\nproperty " +
      t.coord + " z\nelement face 4\nproperty list uint8 float32 uv\nproperty list " + t.count + " " + t.index + " " +
      t.index_name + "\nelement extra 2\nproperty list int short values\nproperty double w\nend_header\n";
  Bytes b{big, header};
  const TriangleSoup s = tetra();
  for (const Vec3& p : s.positions) {
    b.put(static_cast<C>(p.x())).put(std::uint8_t{9}).put(static_cast<C>(p.y())).put(static_cast<C>(p.z()));
  }
  for (const Tri& f : s.faces) {
    b.put(std::uint8_t{2}).put(0.25f).put(0.75f);
    b.put(static_cast<N>(3));
    for (int v : f) b.put(static_cast<I>(v));
  }
  b.put(std::int32_t{1}).put(std::int16_t{5}).put(1.5);
  b.put(std::int32_t{0}).put(2.5);
  return b.data;
}

TEST(ReadPly, BinaryScalarAndListTypesInBothByteOrders) {
  for (bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    const std::vector<std::pair<PlyTypes, std::string>> cases = {
        {{"float", "uchar", "int", "vertex_indices"},
         binary_tetra<float, std::uint8_t, std::int32_t>({"float", "uchar", "int", "vertex_indices"}, big)},
        {{"double", "int", "uint", "vertex_index"},
         binary_tetra<double, std::int32_t, std::uint32_t>({"double", "int", "uint", "vertex_index"}, big)},
        {{"float64", "uint32", "int32", "vertex_indices"},
         binary_tetra<double, std::uint32_t, std::int32_t>({"float64", "uint32", "int32", "vertex_indices"}, big)},
        {{"short", "ushort", "ushort", "vertex_indices"},
         binary_tetra<std::int16_t, std::uint16_t, std::uint16_t>({"short", "ushort", "ushort", "vertex_indices"},
                                                                  big)},
        {{"int8", "int8", "uchar", "vertex_index"},
         binary_tetra<std::int8_t, std::int8_t, std::uint8_t>({"int8", "int8", "uchar", "vertex_index"}, big)},
        {{"uint", "int16", "char", "vertex_indices"},
         binary_tetra<std::uint32_t, std::int16_t, std::int8_t>({"uint", "int16", "char", "vertex_indices"}, big)},
    };
    for (const auto& [types, data] : cases) {
      SCOPED_TRACE(types.coord + " " + types.count + " " + types.index + " " + types.index_name);
      std::vector<std::string> warnings;
      expect_same(read_mem(MeshFormat::Ply, data, "t.ply", &warnings), tetra());
      EXPECT_TRUE(warnings.empty());
    }
  }
}

TEST(ReadPly, AsciiListTypesAndPolygons) {
  const std::string data =
      "ply\r\nformat ascii 1.0\r\nelement vertex 4\r\nproperty int16 x\r\nproperty int16 y\r\nproperty int16 z\r\n"
      "element face 1\r\nproperty list uint int vertex_index\r\nend_header\r\n"
      "0 0 0\r\n1 0 0\r\n1 1 0\r\n0 1 0\r\n4 0 1 2 3\r\n";
  std::vector<std::string> warnings;
  const TriangleSoup s = read_mem(MeshFormat::Ply, data, "q.ply", &warnings);
  EXPECT_EQ(s.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], HasSubstr("1 polygon "));
}

TEST(ReadStl, AsciiCubeIsWeldedIncludingNegativeZero) {
  const ReadResult r = read_mesh(tiny("cube_ascii.stl"));
  EXPECT_EQ(r.soup.positions.size(), 8u);
  EXPECT_EQ(r.soup.faces.size(), 12u);
  EXPECT_EQ(r.soup.positions[0], Vec3(0, 0, 0));
  EXPECT_FALSE(std::signbit(r.soup.positions[0].x()));
}

TEST(ReadStl, BinaryCubeIsWeldedInOrderOfFirstAppearance) {
  const ReadResult r = read_mesh(tiny("cube_binary.stl"));
  ASSERT_EQ(r.soup.positions.size(), 8u);
  ASSERT_EQ(r.soup.faces.size(), 12u);
  // First triangle of the file is corners (0,3,2) of the cube: they become vertices 0, 1, 2.
  EXPECT_EQ(r.soup.faces[0], (Tri{0, 1, 2}));
  EXPECT_EQ(r.soup.positions[1], Vec3(0, 1, 0));
}

TEST(ReadStl, BinaryWhoseHeaderStartsWithSolid) {
  std::string data = read_file(tiny("cube_binary.stl"));
  data.replace(0, 5, "solid");
  EXPECT_EQ(read_mem(MeshFormat::Stl, data, "s.stl").faces.size(), 12u);
}

}  // namespace
}  // namespace freeform::test
