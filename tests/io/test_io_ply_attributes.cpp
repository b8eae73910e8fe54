// PLY attributes (normals, texture coordinates, colours, other properties, polygons), the
// FileSource that rewrites a file with new positions and nothing else changed, and write_ply
// from generic attributes.
#include "freeform/common/error.h"
#include "freeform/io/mesh_io.h"
#include "io_test_util.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <array>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace freeform {
namespace {

using test::Bytes;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

ReadResult read_ply_data(std::string_view data, const std::string& name = "t.ply") {
  ReadResult r;
  read_ply(data, name, r);
  return r;
}

std::string rewrite(const ReadResult& r, std::span<const Vec3> positions) {
  std::vector<std::pair<std::string, std::string>> companions;
  const std::string out = r.source->rewrite(r, positions, companions, "out.ply");
  EXPECT_TRUE(companions.empty());
  return out;
}

// Translated by (1, 2, 3) and scaled by 1.5 about the origin.
std::vector<Vec3> moved(const std::vector<Vec3>& positions) {
  std::vector<Vec3> out;
  for (const Vec3& p : positions) out.push_back(1.5 * p + Vec3(1, 2, 3));
  return out;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template <class T>
std::string shortest(T value) {
  char buf[32];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  EXPECT_EQ(ec, std::errc());
  return std::string(buf, ptr);
}


void expect_same_polygons(const MeshAttributes& a, const MeshAttributes& b) {
  EXPECT_EQ(a.polygons.offsets, b.polygons.offsets);
  EXPECT_EQ(a.polygons.corners, b.polygons.corners);
  EXPECT_EQ(a.triangle_polygon, b.triangle_polygon);
}

void expect_same_named(const std::vector<NamedAttribute>& a, const std::vector<NamedAttribute>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].name, b[i].name);
    EXPECT_EQ(a[i].width, b[i].width);
    EXPECT_EQ(a[i].values, b[i].values) << a[i].name;
  }
}

// Positions as a float property holds them.
void expect_float_positions(const std::vector<Vec3>& got, const std::vector<Vec3>& expected) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t v = 0; v < got.size(); ++v)
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(static_cast<float>(got[v][k]), static_cast<float>(expected[v][k])) << "vertex " << v << " axis " << k;
}

void expect_unit_normals(const CornerAttribute& n) {
  ASSERT_EQ(n.width, 3);
  for (int r = 0; r < n.rows(); ++r) {
    const auto i = static_cast<std::size_t>(r) * 3;
    EXPECT_NEAR(Vec3(n.values[i], n.values[i + 1], n.values[i + 2]).norm(), 1.0, 1e-5) << "row " << r;
  }
}

// ---- assimp-testmodels -------------------------------------------------------------------------

// An ascii PLY with one vertex per line and the vertex element first, with the position and
// normal values of the vertices replaced by '#' (spacing kept): what a rewrite must not change.
std::string mask_vertex_values(const std::string& data, std::size_t nv) {
  const std::size_t body = data.find("end_header\n") + 11;
  std::vector<std::string> names;  // vertex property names in order
  std::istringstream header(data.substr(data.find("element vertex"), body));
  std::string line;
  std::getline(header, line);
  while (std::getline(header, line) && line.rfind("property ", 0) == 0) {
    std::istringstream words(line);
    std::string word, last;
    while (words >> word) last = word;
    names.push_back(last);
  }
  std::size_t at = body;
  std::string out = data.substr(0, body);
  for (std::size_t v = 0; v < nv; ++v) {
    const std::size_t end = data.find('\n', at);
    std::size_t k = 0;
    for (std::size_t i = at; i < end;) {
      if (data[i] == ' ') {
        out += data[i++];
        continue;
      }
      const std::size_t token_end = std::min(data.find(' ', i), end);
      const std::string& name = k < names.size() ? names[k] : std::string();
      const bool masked = name == "x" || name == "y" || name == "z" || name == "nx" || name == "ny" || name == "nz";
      out += masked ? std::string("#") : data.substr(i, token_end - i);
      ++k;
      i = token_end;
    }
    out += '\n';
    at = end + 1;
  }
  return out + data.substr(at);
}

const std::filesystem::path kAssimpPly = "/usr/share/assimp/models/PLY";

TEST(PlyAssimpModels, RewriteKeepsTheFileAndMovesOnlyPositions) {
  if (!std::filesystem::is_directory(kAssimpPly)) GTEST_SKIP() << kAssimpPly << " missing (Debian's assimp-testmodels)";
  for (const char* file : {"cube.ply", "cube_binary.ply", "cube_uv.ply", "float-color.ply", "Wuson.ply"}) {
    SCOPED_TRACE(file);
    const std::string data = slurp(kAssimpPly / file);
    const ReadResult r = read_ply_data(data, file);
    const bool has_normals = !r.attributes.normal.empty();
    // Same positions: the same bytes (normals are recomputed only around moved vertices).
    EXPECT_EQ(rewrite(r, r.soup.positions), data);
    // Moved positions: read back as written (float files: to float precision), the rest unchanged.
    const std::vector<Vec3> target = moved(r.soup.positions);
    const std::string moved_data = rewrite(r, target);
    if (!r.source->binary()) {
      EXPECT_EQ(mask_vertex_values(moved_data, target.size()), mask_vertex_values(data, target.size()));
    } else {  // cube_binary.ply: 8 vertices of three floats
      const std::size_t vertices_end = data.find("end_header\n") + 11 + 8 * 12;
      EXPECT_EQ(moved_data.substr(0, vertices_end - 8 * 12), data.substr(0, vertices_end - 8 * 12));
      EXPECT_EQ(moved_data.substr(vertices_end), data.substr(vertices_end));
    }
    const ReadResult m = read_ply_data(moved_data, file);
    expect_float_positions(m.soup.positions, target);
    EXPECT_EQ(m.soup.faces, r.soup.faces);
    expect_same_polygons(m.attributes, r.attributes);
    EXPECT_EQ(m.attributes.uv.values, r.attributes.uv.values);
    EXPECT_EQ(m.attributes.uv.index, r.attributes.uv.index);
    expect_same_named(m.attributes.vertex, r.attributes.vertex);
    expect_same_named(m.attributes.face, r.attributes.face);
    EXPECT_EQ(m.source->binary(), r.source->binary());
    if (has_normals) {
      expect_unit_normals(m.attributes.normal);
      // Translation and uniform scaling keep the directions, and these files store flat normals
      // (vertices split per face): the recomputed ones are the file's to its 6 decimals.
      ASSERT_EQ(m.attributes.normal.values.size(), r.attributes.normal.values.size());
      for (std::size_t i = 0; i < r.attributes.normal.values.size(); ++i)
        ASSERT_NEAR(m.attributes.normal.values[i], r.attributes.normal.values[i], 2e-4) << "value " << i;
    }
  }
}

TEST(PlyAssimpModels, AttributesOfTheFiles) {
  if (!std::filesystem::is_directory(kAssimpPly)) GTEST_SKIP() << kAssimpPly << " missing (Debian's assimp-testmodels)";
  {
    const ReadResult r = read_ply_data(slurp(kAssimpPly / "cube_uv.ply"), "cube_uv.ply");
    EXPECT_EQ(r.format, MeshFormat::Ply);
    EXPECT_EQ(r.attributes.polygons.size(), 6);
    EXPECT_EQ(r.attributes.triangle_polygon.size(), 12u);
    EXPECT_EQ(r.attributes.uv.width, 2);
    EXPECT_EQ(r.attributes.uv.rows(), 24);
    EXPECT_EQ(r.attributes.uv.index, r.attributes.polygons.corners);
    EXPECT_EQ(r.attributes.uv.values[2], 1.0);  // vertex 1: s t = 1 0
    EXPECT_EQ(r.attributes.normal.rows(), 24);
    EXPECT_EQ(r.attributes.normal.values[2], -1.0);  // vertex 0: 0 0 -1
    EXPECT_TRUE(r.attributes.vertex.empty());
    EXPECT_FALSE(r.source->binary());
  }
  {
    const ReadResult r = read_ply_data(slurp(kAssimpPly / "float-color.ply"), "float-color.ply");
    ASSERT_EQ(r.attributes.vertex.size(), 1u);
    EXPECT_EQ(r.attributes.vertex[0].name, "color");
    EXPECT_EQ(r.attributes.vertex[0].width, 4);
    EXPECT_THAT(r.attributes.vertex[0].values, ElementsAre(0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1));
  }
  EXPECT_TRUE(read_ply_data(slurp(kAssimpPly / "cube_binary.ply"), "cube_binary.ply").source->binary());
}

// pond.0.ply (a binary point cloud with normals, diffuse colours and a point size) has no face
// element: it is refused as before.
TEST(PlyAssimpModels, PointCloudWithoutFacesIsRefused) {
  if (!std::filesystem::is_regular_file(kAssimpPly / "pond.0.ply")) GTEST_SKIP() << "pond.0.ply missing";
  try {
    read_ply_data(slurp(kAssimpPly / "pond.0.ply"), "pond.0.ply");
    ADD_FAILURE() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("no faces"));
  }
}

// ---- generated files -----------------------------------------------------------------------------

// A quad, a pentagon and a triangle over 8 vertices, with a uchar colour, an int property and a
// vertex list, a float face property and a face list, an edge element and comments.
const std::vector<Vec3> kPositions = {Vec3(0, 0, 0),         Vec3(1, 0, 0),      Vec3(1, 1, 0.5),  Vec3(0, 1, 0),
                                      Vec3(2, 0.5, -0.25), Vec3(1.5, 2, 0.1), Vec3(0.5, 2.5, 1.0 / 3), Vec3(-1, 0.5, 0)};
const std::vector<std::vector<int>> kPolygons = {{0, 1, 2, 3}, {3, 2, 4, 5, 6}, {0, 3, 7}};
const std::vector<float> kWeights = {0.5f, 1.25f, -2};

std::array<int, 3> color_of(std::size_t v) {
  return {static_cast<int>(10 * v), static_cast<int>(255 - 10 * v), 7};
}
int quality_of(std::size_t v) { return static_cast<int>(v) * 1000 - 3000; }

const char* kGeneratedHeader =
    "comment generated for freeform's tests\n"
    "obj_info by hand\n"
    "element vertex 8\n"
    "property float x\nproperty float y\nproperty double z\n"
    "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    "property int quality\n"
    "property list uchar float extra\n"
    "element face 3\n"
    "property list uchar int vertex_indices\n"
    "property float weight\n"
    "property list uchar float texcoord\n"
    "element edge 2\n"
    "property int vertex1\nproperty int vertex2\n"
    "end_header\n";

// x and y are floats, z a double; ascii values use the shortest form (as a rewrite writes them)
// with irregular spacing that a rewrite must keep.
std::string generated_ascii(const std::vector<Vec3>& p) {
  std::string out = std::string("ply\nformat ascii 1.0\n") + kGeneratedHeader;
  for (std::size_t v = 0; v < p.size(); ++v) {
    const std::array<int, 3> c = color_of(v);
    const char* gap = v % 2 == 0 ? " " : "  \t";
    out += shortest(static_cast<float>(p[v].x())) + gap + shortest(static_cast<float>(p[v].y())) + " " +
           shortest(p[v].z()) + gap + std::to_string(c[0]) + " " + std::to_string(c[1]) + " " + std::to_string(c[2]) +
           " " + std::to_string(quality_of(v)) + " " + std::to_string(v % 3);
    for (std::size_t j = 0; j < v % 3; ++j) out += " 0.5";
    out += v % 2 == 0 ? "\n" : "  \r\n";
  }
  for (std::size_t f = 0; f < kPolygons.size(); ++f) {
    out += std::to_string(kPolygons[f].size());
    for (int v : kPolygons[f]) out += " " + std::to_string(v);
    out += " " + shortest(kWeights[f]) + (f == 0 ? " 2 0.25 0.75\n" : " 0\n");
  }
  return out + "0 1\n2   3\n";
}

std::string generated_binary(const std::vector<Vec3>& p, bool big) {
  Bytes b{big, std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") + " 1.0\n" +
                   kGeneratedHeader};
  for (std::size_t v = 0; v < p.size(); ++v) {
    const std::array<int, 3> c = color_of(v);
    b.put(static_cast<float>(p[v].x())).put(static_cast<float>(p[v].y())).put(p[v].z());
    for (int k = 0; k < 3; ++k) b.put(static_cast<std::uint8_t>(c[static_cast<std::size_t>(k)]));
    b.put(static_cast<std::int32_t>(quality_of(v))).put(static_cast<std::uint8_t>(v % 3));
    for (std::size_t j = 0; j < v % 3; ++j) b.put(0.5f);
  }
  for (std::size_t f = 0; f < kPolygons.size(); ++f) {
    b.put(static_cast<std::uint8_t>(kPolygons[f].size()));
    for (int v : kPolygons[f]) b.put(static_cast<std::int32_t>(v));
    b.put(kWeights[f]);
    if (f == 0) {
      b.put(std::uint8_t{2}).put(0.25f).put(0.75f);
    } else {
      b.put(std::uint8_t{0});
    }
  }
  b.put(std::int32_t{0}).put(std::int32_t{1}).put(std::int32_t{2}).put(std::int32_t{3});
  return b.data;
}

struct Encoded {
  const char* name;
  std::string (*make)(const std::vector<Vec3>&);
  bool binary;
};
const Encoded kEncodings[] = {
    {"ascii", generated_ascii, false},
    {"binary little endian", [](const std::vector<Vec3>& p) { return generated_binary(p, false); }, true},
    {"binary big endian", [](const std::vector<Vec3>& p) { return generated_binary(p, true); }, true},
};

TEST(PlyAttributes, GeneratedFilesExposePolygonsColoursAndProperties) {
  for (const Encoded& e : kEncodings) {
    SCOPED_TRACE(e.name);
    const ReadResult r = read_ply_data(e.make(kPositions), "g.ply");
    EXPECT_EQ(r.format, MeshFormat::Ply);
    expect_float_positions(r.soup.positions, kPositions);
    EXPECT_EQ(r.soup.positions[6].z(), 1.0 / 3);  // a double property: exact
    // The pentagon turns clockwise at corner 2: its fan from corner 3 would overlap itself.
    EXPECT_EQ(r.soup.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}, {6, 3, 2}, {5, 6, 2}, {4, 5, 2}, {0, 3, 7}}));
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_EQ(r.warnings[0],
              "2 polygons with more than 3 vertices triangulated into 5 triangles (1 non-convex one by ear clipping, "
              "the others fanned)");
    const MeshAttributes& a = r.attributes;
    EXPECT_EQ(a.polygons.offsets, (std::vector<int>{0, 4, 9, 12}));
    EXPECT_EQ(a.polygons.corners, (std::vector<int>{0, 1, 2, 3, 3, 2, 4, 5, 6, 0, 3, 7}));
    EXPECT_EQ(a.triangle_polygon, (std::vector<int>{0, 0, 1, 1, 1, 2}));
    EXPECT_TRUE(a.normal.empty());
    EXPECT_TRUE(a.uv.empty());
    ASSERT_EQ(a.vertex.size(), 2u);  // the list 'extra' is not an attribute
    EXPECT_EQ(a.vertex[0].name, "color");
    EXPECT_EQ(a.vertex[0].width, 3);
    ASSERT_EQ(a.vertex[0].values.size(), 24u);
    EXPECT_EQ(a.vertex[0].values[3 * 2 + 1], 235.0 / 255);
    EXPECT_EQ(a.vertex[0].values[3 * 7 + 2], 7.0 / 255);
    EXPECT_EQ(a.vertex[1].name, "quality");
    EXPECT_EQ(a.vertex[1].width, 1);
    EXPECT_THAT(a.vertex[1].values, ElementsAre(-3000, -2000, -1000, 0, 1000, 2000, 3000, 4000));
    ASSERT_EQ(a.face.size(), 1u);  // the list 'texcoord' is not an attribute
    EXPECT_EQ(a.face[0].name, "weight");
    EXPECT_THAT(a.face[0].values, ElementsAre(0.5, 1.25, -2));
    EXPECT_EQ(r.source->binary(), e.binary);
    EXPECT_EQ(r.source->kept_only_by_rewrite(),
              "the list property 'extra' of 'vertex', the list property 'texcoord' of 'face', the element 'edge' and "
              "comments");
  }
}

TEST(PlyAttributes, RewriteChangesOnlyThePositions) {
  std::vector<Vec3> target = moved(kPositions);
  target[5] = kPositions[5];  // an unchanged vertex keeps its spelling
  target[2].z() = 0.1;        // a double property: written exactly
  for (const Encoded& e : kEncodings) {
    SCOPED_TRACE(e.name);
    const std::string data = e.make(kPositions);
    const ReadResult r = read_ply_data(data, "g.ply");
    EXPECT_EQ(rewrite(r, r.soup.positions), data);
    const std::string out = rewrite(r, target);
    EXPECT_EQ(out, e.make(target));
    const ReadResult m = read_ply_data(out, "g.ply");
    expect_float_positions(m.soup.positions, target);
    EXPECT_EQ(m.soup.positions[2].z(), 0.1);
    expect_same_polygons(m.attributes, r.attributes);
    expect_same_named(m.attributes.vertex, r.attributes.vertex);
    expect_same_named(m.attributes.face, r.attributes.face);
  }
}

TEST(PlyAttributes, RewriteNeedsOnePositionPerVertex) {
  const ReadResult r = read_ply_data(generated_ascii(kPositions), "g.ply");
  const std::vector<Vec3> fewer(kPositions.begin(), kPositions.end() - 1);
  std::vector<std::pair<std::string, std::string>> companions;
  EXPECT_THROW(r.source->rewrite(r, fewer, companions, "out.ply"), InvalidInput);
}

// A triangle with the given vertex properties (values per vertex in `rows`), ascii.
std::string triangle_with(const std::string& properties, const std::vector<std::string>& rows) {
  std::string out = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n" +
                    properties + "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const char* xyz[3] = {"0 0 0", "1 0 0", "0 1 0"};
  for (std::size_t v = 0; v < 3; ++v) out += std::string(xyz[v]) + " " + rows[v] + "\n";
  return out + "3 0 1 2\n";
}

TEST(PlyAttributes, TextureCoordinateNamesAndColourTypes) {
  for (const char* uv : {"u v", "s t", "texture_u texture_v", "texture_s texture_t"}) {
    SCOPED_TRACE(uv);
    std::istringstream names(uv);
    std::string a, b;
    names >> a >> b;
    const ReadResult r = read_ply_data(triangle_with("property float " + a + "\nproperty float " + b + "\n",
                                                     {"0.25 0.5", "1 0", "0 1"}));
    EXPECT_EQ(r.attributes.uv.width, 2);
    EXPECT_THAT(r.attributes.uv.values, ElementsAre(0.25, 0.5, 1, 0, 0, 1));
    EXPECT_THAT(r.attributes.uv.index, ElementsAre(0, 1, 2));
    EXPECT_TRUE(r.attributes.vertex.empty());
  }
  {
    const ReadResult r = read_ply_data(triangle_with(
        "property ushort blue\nproperty ushort green\nproperty ushort red\nproperty ushort alpha\nproperty short s\n",
        {"0 65535 65535 0 -4", "65535 0 0 65535 5", "0 0 0 0 6"}));
    ASSERT_EQ(r.attributes.vertex.size(), 2u);  // "s" without "t" is a property like any other
    EXPECT_EQ(r.attributes.vertex[0].name, "color");
    EXPECT_EQ(r.attributes.vertex[0].width, 4);
    EXPECT_THAT(r.attributes.vertex[0].values, ElementsAre(1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0));
    EXPECT_EQ(r.attributes.vertex[1].name, "s");
    EXPECT_THAT(r.attributes.vertex[1].values, ElementsAre(-4, 5, 6));
    EXPECT_TRUE(r.attributes.uv.empty());
  }
  {
    const ReadResult r = read_ply_data(triangle_with(
        "property float nx\nproperty float ny\nproperty float nz\nproperty char diffuse_red\n"
        "property char diffuse_green\nproperty char diffuse_blue\n",
        {"0 0 1 127 0 0", "0 0 1 0 127 0", "0 0 1 0 0 127"}));
    EXPECT_EQ(r.attributes.normal.width, 3);
    EXPECT_THAT(r.attributes.normal.values, ElementsAre(0, 0, 1, 0, 0, 1, 0, 0, 1));
    EXPECT_THAT(r.attributes.normal.index, ElementsAre(0, 1, 2));
    ASSERT_EQ(r.attributes.vertex.size(), 1u);
    EXPECT_THAT(r.attributes.vertex[0].values, ElementsAre(1, 0, 0, 0, 1, 0, 0, 0, 1));
  }
  // A value that is not a number is an error naming the element and the property.
  try {
    read_ply_data(triangle_with("property uchar red\n", {"1", "x", "3"}), "bad.ply");
    ADD_FAILURE() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_THAT(e.what(), HasSubstr("bad.ply:12: vertex 1: invalid value 'x' for property 'red'"));
  }
}

TEST(PlyAttributes, IntegerPositionsAreRoundedAndClamped) {
  const std::string data =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty short x\nproperty uchar y\nproperty int z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const ReadResult r = read_ply_data(data);
  const std::vector<Vec3> target = {Vec3(1.6, -3, 2.5), Vec3(40000, 300, -2.5), Vec3(-40000, 1.4, 7)};
  EXPECT_EQ(rewrite(r, target),
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty short x\nproperty uchar y\nproperty int z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_header\n2 0 3\n32767 255 -3\n-32768 1 7\n"
            "3 0 1 2\n");
}

// ---- write_ply from generic attributes ---------------------------------------------------------

// A quad and a triangle sharing an edge, with per-vertex uv and normals (no seams), a colour
// with alpha, a custom vertex property, a face colour and a custom face property.
struct Generic {
  TriangleSoup soup;
  MeshAttributes attributes;
};

Generic generic_mesh() {
  Generic g;
  g.soup.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0.5, 0.1)};
  g.soup.faces = {Tri{0, 1, 2}, Tri{0, 2, 3}, Tri{1, 4, 2}};
  MeshAttributes& a = g.attributes;
  a.polygons.add(std::vector<int>{0, 1, 2, 3});
  a.polygons.add(std::vector<int>{1, 4, 2});
  a.triangle_polygon = {0, 0, 1};
  // Corner rows in another order than the vertices, with one value stored twice (no seam).
  a.uv.width = 2;
  a.uv.values = {0.5, 0.25, 0, 0, 0.5, 0.25, 1, 1, 0, 1, 1.0 / 3, 0.7};
  a.uv.index = {1, 0, 3, 4, 2, 5, 3};  // vertex 1: rows 0 and 2, equal values
  a.normal.width = 3;
  for (int v = 0; v < 5; ++v) {
    const Vec3 n = Vec3(0.1 * v, -0.2, 1).normalized();
    a.normal.values.insert(a.normal.values.end(), {n.x(), n.y(), n.z()});
  }
  a.normal.index = a.polygons.corners;
  a.vertex.push_back({"color", 4, {1, 0, 0, 1, 0, 1, 0, 0.5, 0, 0, 1, 0, 0.2, 0.4, 0.6, 0.8, 1, 1, 1, 1}});
  a.vertex.push_back({"temperature", 1, {0.1, -2.5, 1e300, 3.0, 1.0 / 3}});
  a.face.push_back({"color", 3, {1, 0.5, 0, 0, 0.5, 1}});
  a.face.push_back({"material_id", 1, {7, 42}});
  return g;
}

TEST(WritePly, GenericAttributesRoundTrip) {
  const Generic g = generic_mesh();
  for (bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    std::vector<std::string> dropped;
    const std::string data = write_ply(g.soup, binary, g.attributes, dropped);
    EXPECT_TRUE(dropped.empty()) << dropped.front();
    EXPECT_THAT(data, HasSubstr(binary ? "format binary_little_endian 1.0\n" : "format ascii 1.0\n"));
    EXPECT_THAT(data, HasSubstr("property double x\nproperty double y\nproperty double z\nproperty float nx\n"
                                "property float ny\nproperty float nz\nproperty float u\nproperty float v\n"
                                "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                                "property uchar alpha\nproperty double temperature\nelement face 2\n"
                                "property list uchar int vertex_indices\nproperty uchar red\n"
                                "property uchar green\nproperty uchar blue\nproperty double material_id\n"));
    const ReadResult r = read_ply_data(data, "w.ply");
    EXPECT_EQ(r.soup.positions, g.soup.positions);  // doubles: exact
    EXPECT_EQ(r.soup.faces, g.soup.faces);
    expect_same_polygons(r.attributes, g.attributes);
    EXPECT_EQ(r.attributes.uv.index, r.attributes.polygons.corners);
    const std::vector<double> uv_per_vertex = {0, 0, 0.5, 0.25, 1, 1, 0, 1, 1.0 / 3, 0.7};
    ASSERT_EQ(r.attributes.uv.values.size(), uv_per_vertex.size());
    for (std::size_t i = 0; i < uv_per_vertex.size(); ++i)
      EXPECT_EQ(static_cast<float>(r.attributes.uv.values[i]), static_cast<float>(uv_per_vertex[i])) << i;
    ASSERT_EQ(r.attributes.normal.values.size(), g.attributes.normal.values.size());
    for (std::size_t i = 0; i < g.attributes.normal.values.size(); ++i)
      EXPECT_EQ(static_cast<float>(r.attributes.normal.values[i]), static_cast<float>(g.attributes.normal.values[i]));
    ASSERT_EQ(r.attributes.vertex.size(), 2u);
    EXPECT_EQ(r.attributes.vertex[0].name, "color");
    EXPECT_EQ(r.attributes.vertex[0].width, 4);
    for (std::size_t i = 0; i < 20; ++i)  // uchar: the nearest of 256 levels
      EXPECT_EQ(r.attributes.vertex[0].values[i], std::round(g.attributes.vertex[0].values[i] * 255) / 255) << i;
    EXPECT_EQ(r.attributes.vertex[1].name, "temperature");
    EXPECT_EQ(r.attributes.vertex[1].values, g.attributes.vertex[1].values);
    ASSERT_EQ(r.attributes.face.size(), 2u);
    EXPECT_EQ(r.attributes.face[0].name, "color");
    EXPECT_THAT(r.attributes.face[0].values, ElementsAre(1, 128.0 / 255, 0, 0, 128.0 / 255, 1));
    expect_same_named({r.attributes.face[1]}, {g.attributes.face[1]});
  }
}

TEST(WritePly, WithoutPolygonsTheSoupTrianglesAreWritten) {
  Generic g = generic_mesh();
  g.attributes = {};
  g.attributes.face.push_back({"area", 1, {0.5, 0.5, 0.25}});  // one per soup triangle
  std::vector<std::string> dropped;
  const ReadResult r = read_ply_data(write_ply(g.soup, false, g.attributes, dropped));
  EXPECT_TRUE(dropped.empty());
  EXPECT_EQ(r.soup.faces, g.soup.faces);
  EXPECT_EQ(r.attributes.polygons.size(), 3);
  EXPECT_THAT(r.attributes.face[0].values, ElementsAre(0.5, 0.5, 0.25));
  EXPECT_TRUE(r.warnings.empty());
}

TEST(WritePly, SeamsAndBadNamesAreDroppedAndSaid) {
  Generic g = generic_mesh();
  g.attributes.uv.values[0] = 0.75;  // vertex 1's two rows now differ: a seam
  g.attributes.normal.index[4] = 4;  // vertex 1 in the triangle gets vertex 4's normal: a seam
  g.attributes.vertex.push_back({"bad name", 1, {0, 0, 0, 0, 0}});
  g.attributes.vertex.push_back({"nx", 1, {0, 0, 0, 0, 0}});
  g.attributes.vertex.push_back({"temperature", 1, {0, 0, 0, 0, 0}});
  g.attributes.vertex.push_back({"pair", 2, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9}});
  std::vector<std::string> dropped;
  const std::string data = write_ply(g.soup, true, g.attributes, dropped);
  EXPECT_THAT(dropped, ElementsAre("normals with seams (PLY stores one per vertex)",
                                   "texture coordinates with seams (PLY stores one per vertex)",
                                   "vertex property 'bad name' (not a valid PLY property name)",
                                   "vertex property 'nx' (a name PLY readers give another meaning)",
                                   "vertex property 'temperature' (a second property with that name)"));
  const ReadResult r = read_ply_data(data);
  EXPECT_TRUE(r.attributes.uv.empty());
  EXPECT_TRUE(r.attributes.normal.empty());
  ASSERT_EQ(r.attributes.vertex.size(), 4u);
  EXPECT_EQ(r.attributes.vertex[2].name, "pair_0");
  EXPECT_THAT(r.attributes.vertex[3].values, ElementsAre(1, 3, 5, 7, 9));
  EXPECT_EQ(r.soup.positions, g.soup.positions);
}

TEST(WritePly, InconsistentAttributesAreRefused) {
  Generic g = generic_mesh();
  g.attributes.vertex[1].values.pop_back();
  std::vector<std::string> dropped;
  EXPECT_THROW(write_ply(g.soup, true, g.attributes, dropped), InvalidInput);
  g = generic_mesh();
  g.attributes.polygons.corners[5] = 9;
  EXPECT_THROW(write_ply(g.soup, true, g.attributes, dropped), InvalidInput);
  g = generic_mesh();
  g.attributes.uv.index.pop_back();
  EXPECT_THROW(write_ply(g.soup, true, g.attributes, dropped), InvalidInput);
}

// ---- normals -------------------------------------------------------------------------------------

// The unit cube as 8 vertices and 6 outward quads, with per-vertex normals: the normalized
// average of a corner's three face normals, (+-1, +-1, +-1) / sqrt(3).
std::string cube_with_normals(bool binary, const std::vector<Vec3>& p, const std::vector<Vec3>& n) {
  const char* header =
      " 1.0\nelement vertex 8\nproperty double x\nproperty double y\nproperty double z\n"
      "property float nx\nproperty float ny\nproperty float nz\nelement face 6\n"
      "property list uchar int vertex_indices\nend_header\n";
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  Bytes b{false, std::string("ply\nformat ") + (binary ? "binary_little_endian" : "ascii") + header};
  for (std::size_t v = 0; v < 8; ++v) {
    if (binary) {
      b.put(p[v].x()).put(p[v].y()).put(p[v].z());
      b.put(static_cast<float>(n[v].x())).put(static_cast<float>(n[v].y())).put(static_cast<float>(n[v].z()));
    } else {
      b.data += shortest(p[v].x()) + " " + shortest(p[v].y()) + " " + shortest(p[v].z()) + " " +
                shortest(static_cast<float>(n[v].x())) + " " + shortest(static_cast<float>(n[v].y())) + " " +
                shortest(static_cast<float>(n[v].z())) + "\n";
    }
  }
  for (const auto& q : quads) {
    if (binary) {
      b.put(std::uint8_t{4});
      for (int v : q) b.put(static_cast<std::int32_t>(v));
    } else {
      b.data += "4 " + std::to_string(q[0]) + " " + std::to_string(q[1]) + " " + std::to_string(q[2]) + " " +
                std::to_string(q[3]) + "\n";
    }
  }
  return b.data;
}

TEST(PlyNormals, MovedCubeGetsTheRotatedCornerNormals) {
  std::vector<Vec3> corners;
  std::vector<Vec3> normals;
  for (int v = 0; v < 8; ++v) {
    const Vec3 c((v & 1) != 0 ? 1 : 0, (v & 2) != 0 ? 1 : 0, (v & 4) != 0 ? 1 : 0);
    corners.push_back(Vec3(c.x(), c.y(), c.z()));
    normals.push_back((2 * c - Vec3::Ones()).normalized());
  }
  // Vertex order 0..7 by bits is not a loop order: renumber so that the quads above are faces.
  const std::vector<Vec3> p = {corners[0], corners[1], corners[3], corners[2],
                               corners[4], corners[5], corners[7], corners[6]};
  const std::vector<Vec3> n = {normals[0], normals[1], normals[3], normals[2],
                               normals[4], normals[5], normals[7], normals[6]};
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Vec3> target;
  for (const Vec3& x : p) target.push_back(rotation * x + Vec3(5, -1, 2));
  for (bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary" : "ascii");
    const std::string data = cube_with_normals(binary, p, n);
    const ReadResult r = read_ply_data(data, "cube.ply");
    EXPECT_EQ(rewrite(r, p), data);
    const std::string out = rewrite(r, target);
    std::vector<Vec3> rotated;
    for (const Vec3& x : n) rotated.push_back(rotation * x);
    const ReadResult m = read_ply_data(out, "cube.ply");
    EXPECT_EQ(m.soup.positions, target);
    std::vector<Vec3> written;
    for (std::size_t v = 0; v < 8; ++v) {
      const double* w = &m.attributes.normal.values[v * 3];
      written.emplace_back(w[0], w[1], w[2]);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(written[v][k], rotated[v][k], 1e-7) << "vertex " << v;
    }
    EXPECT_EQ(out, cube_with_normals(binary, target, written));  // nothing else changed
  }
}

}  // namespace
}  // namespace freeform
