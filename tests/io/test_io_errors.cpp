// Malformed input: every error is an IoError naming the file and the line (text) or element.
#include "io_test_util.h"

#include <limits>

namespace freeform::test {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

const std::string kObjTri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(ObjErrors, MalformedInput) {
  struct Case {
    std::string data;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"", {"bad.obj: empty file"}},
      {"# only a comment\n", {"bad.obj: no vertices"}},
      {kObjTri, {"bad.obj: no faces"}},
      {kObjTri + "f 1 2 4\n", {"bad.obj:4:", "face 0", "index 4 out of range"}},
      {kObjTri + "f 1 2 3\nf 3 2 1 9\n", {"bad.obj:5:", "face 1", "index 9"}},
      {kObjTri + "f 0 1 2\n", {"bad.obj:4:", "index 0"}},
      {kObjTri + "f -4 -1 -2\n", {"bad.obj:4:", "-4"}},
      {kObjTri + "f 1 2\n", {"bad.obj:4:", "face 0 has 2 vertices"}},
      {kObjTri + "f 1 x 2\n", {"bad.obj:4:", "invalid vertex index 'x'"}},
      {kObjTri + "f 1 2 99999999999999999999999\n", {"bad.obj:4:", "face 0"}},
      {"v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", {"bad.obj:2:", "vertex 1", "non-finite"}},
      {"v 0 0 0\nv 1 0 0\nv inf 1 0\nf 1 2 3\n", {"bad.obj:3:", "vertex 2", "non-finite"}},
      {"v 0 0 0\nv 1 0 1e999\n", {"bad.obj:2:", "vertex 1"}},
      {"v 0 0\n", {"bad.obj:1:", "fewer than 3"}},
      {"v 0 0 0\nv 1 0 0\n\x7f\x45LF\x02\x01\x01\x00\x00", {"bad.obj:3:", "binary data at line 3"}},
      {std::string("v 0 0 0\nv 1 0\0 0\n", 18), {"bad.obj:2:", "binary data at line 2"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.data);
    const std::string msg = read_error(MeshFormat::Obj, c.data, "bad.obj");
    for (const std::string& e : c.expected) EXPECT_THAT(msg, HasSubstr(e));
  }
}

TEST(OffErrors, MalformedInput) {
  struct Case {
    std::string data;
    std::vector<std::string> expected;
  };
  const std::string tri = "0 0 0\n1 0 0\n0 1 0\n";
  const std::vector<Case> cases = {
      {"", {"bad.off: empty file"}},
      {"# nothing\n\n", {"bad.off", "no OFF header"}},
      {"3 1 0\n" + tri + "3 0 1 2\n", {"bad.off:1:", "missing OFF header"}},
      {"OFF\n", {"bad.off:1:", "vertex count"}},
      {"OFF\n4 1 0\n" + tri, {"bad.off:5:", "declares 4 vertices, found 3"}},
      {"OFF\n3 2 0\n" + tri + "3 0 1 2\n", {"bad.off:6:", "declares 2 faces, found 1"}},
      {"OFF\n3 0 0\n" + tri, {"bad.off:2:", "no faces"}},
      {"OFF\n0 1 0\n", {"bad.off:2:", "no vertices"}},
      {"OFF 1000000000000 1 0\n0 0 0\n", {"bad.off:1:", "too large"}},
      {"OFF 2000000000 1 0\n0 0 0\n", {"bad.off:2:", "declares 2000000000 vertices, found 1"}},
      {"OFF 99999999999999999999999999 1 0\n", {"bad.off:1:", "invalid vertex count"}},
      {"OFF -3 1 0\n", {"bad.off:1:", "invalid vertex count"}},
      {"OFF\n3 1 0\n" + tri + "3 0 1 9\n", {"bad.off:6:", "face 0", "index 9 out of range"}},
      {"OFF\n3 1 0\n" + tri + "3 0 -1 2\n", {"bad.off:6:", "face 0", "index -1"}},
      {"OFF\n3 1 0\n" + tri + "2 0 1\n", {"bad.off:6:", "face 0 has 2 vertices"}},
      {"OFF\n3 1 0\n" + tri + "4 0 1 2\n", {"bad.off:6:", "declares 4 vertices but lists only 3"}},
      {"OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", {"bad.off:4:", "vertex 1", "non-finite"}},
      {"OFF\n3 1 0\n0 0 0\n1 0\n", {"bad.off:4:", "vertex 1 has fewer than 3"}},
      {"4OFF\n3 1 0\n0 0 0 0\n", {"bad.off:3:", "w = 0"}},
      {"OFF BINARY\n", {"bad.off:1:", "binary OFF"}},
      {"OFF\n3 1 0\n0 0 0\n\x01\x02\x03\n", {"bad.off:4:", "binary data at line 4"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.data);
    const std::string msg = read_error(MeshFormat::Off, c.data, "bad.off");
    for (const std::string& e : c.expected) EXPECT_THAT(msg, HasSubstr(e));
  }
}

const std::string kPlyAsciiHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";

TEST(PlyErrors, HeaderProblems) {
  struct Case {
    std::string data;
    std::vector<std::string> expected;
  };
  const std::string v = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string f = "element face 1\nproperty list uchar int vertex_indices\n";
  const std::vector<Case> cases = {
      {"", {"bad.ply: empty file"}},
      {"plx\n", {"bad.ply:1:", "not a PLY file"}},
      {"ply\nformat binary_middle_endian 1.0\n", {"bad.ply:2:", "unknown PLY format 'binary_middle_endian'"}},
      {"ply\nelement vertex 3\nend_header\n", {"bad.ply:3:", "missing 'format'"}},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float128 x\n", {"bad.ply:4:", "unknown PLY type 'float128'"}},
      {"ply\nformat ascii 1.0\nproperty float x\n", {"bad.ply:3:", "property before any element"}},
      {"ply\nformat ascii 1.0\n" + v + f, {"bad.ply:8:", "end_header"}},
      {"ply\nformat ascii 1.0\nelemnt vertex 3\n", {"bad.ply:3:", "no 'end_header'", "line 3 'elemnt vertex 3' was not understood"}},
      {"ply\nformat ascii 1.0\nelemnt vertex 3\nend_header\n", {"bad.ply", "no 'vertex' element", "line 3 'elemnt vertex 3'"}},
      {"ply\nformat ascii 1.0\nelement vertex 99999999999999999999999\n", {"bad.ply:3:", "invalid element count"}},
      {"ply\nformat ascii 1.0\n" + f + "end_header\n3 0 1 2\n", {"bad.ply", "no 'vertex' element"}},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float z\n" + f + "end_header\n",
       {"bad.ply", "no 'y' property"}},
      {"ply\nformat ascii 1.0\n" + v + "end_header\n0 0 0\n1 0 0\n0 1 0\n", {"bad.ply", "no faces"}},
      {"ply\nformat ascii 1.0\n" + v + "element face 1\nproperty list uchar float vertex_indices\nend_header\n",
       {"bad.ply", "integer item type"}},
      {"ply\nformat ascii 1.0\n" + v + "element face 1\nproperty list float int vertex_indices\nend_header\n",
       {"bad.ply:8:", "count type 'float' must be an integer"}},
      {"ply\nformat ascii 1.0\n" + v + "element face 1\nproperty int vertex_indices\nend_header\n",
       {"bad.ply", "must be a list"}},
      {"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n" + f +
           "end_header\n",
       {"bad.ply", "no vertices"}},
      {"ply\nformat ascii 1.0\n" + v + "element face 0\nproperty list uchar int vertex_indices\nend_header\n",
       {"bad.ply", "no faces"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.data);
    const std::string msg = read_error(MeshFormat::Ply, c.data, "bad.ply");
    for (const std::string& e : c.expected) EXPECT_THAT(msg, HasSubstr(e));
  }
}

TEST(PlyErrors, AsciiBody) {
  struct Case {
    std::string body;
    std::vector<std::string> expected;
  };
  const std::vector<Case> cases = {
      {"0 0 0\n1 0 0\n", {"bad.ply:12:", "unexpected end of file"}},
      {"0 0 0\n1 0 0\n0 1 0\n", {"bad.ply:13:", "unexpected end of file"}},
      {"0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", {"bad.ply:13:", "face 0", "index 3 out of range"}},
      {"0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", {"bad.ply:13:", "face 0", "index -1"}},
      {"0 0 0\n1 0 0\n0 1 0\n2 0 1\n", {"bad.ply:13:", "face 0 has 2 vertices"}},
      {"0 0 0\n1 -inf 0\n0 1 0\n3 0 1 2\n", {"bad.ply:11:", "vertex 1", "non-finite"}},
      {"0 0 0\n1 abc 0\n0 1 0\n3 0 1 2\n", {"bad.ply:11:", "vertex 1", "invalid coordinate"}},
      {"0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", {"bad.ply:13:", "invalid list length"}},
      {std::string("0 0 0\n1 0 0\n\0\0\0\0", 16), {"bad.ply:12:", "binary data at line 12"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.body);
    const std::string msg = read_error(MeshFormat::Ply, kPlyAsciiHead + c.body, "bad.ply");
    for (const std::string& e : c.expected) EXPECT_THAT(msg, HasSubstr(e));
  }
}

std::string binary_head(const std::string& nv, const std::string& nf, const std::string& count_type = "uchar") {
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + nv +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + nf + "\nproperty list " +
         count_type + " int vertex_indices\nend_header\n";
}

Bytes tri_vertices(Bytes b, float y1 = 0.0f) {
  b.put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(y1).put(0.0f).put(0.0f).put(1.0f).put(0.0f);
  return b;
}

TEST(PlyErrors, BinaryBody) {
  {  // fewer vertices than declared: detected before reading
    Bytes b{false, binary_head("5", "1")};
    b = tri_vertices(b);
    b.put(std::uint8_t{3}).put(0).put(1).put(2);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"),
                AllOf(HasSubstr("bad.ply: file truncated"), HasSubstr("vertex: 5 x 12")));
  }
  {  // a header claiming 10^12 elements: no allocation, clear error
    Bytes b{false, binary_head("1000000000000", "1")};
    b = tri_vertices(b);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"), HasSubstr("too large"));
    std::string head = binary_head("3", "1");
    head.insert(head.find("element vertex"), "element junk 1000000000000\nproperty double a\n");
    Bytes c{false, head};
    EXPECT_THAT(read_error(MeshFormat::Ply, c.data, "bad.ply"),
                AllOf(HasSubstr("truncated"), HasSubstr("junk: 1000000000000 x 8")));
  }
  {  // more faces declared than present
    Bytes b{false, binary_head("3", "2")};
    b = tri_vertices(b);
    b.put(std::uint8_t{3}).put(0).put(1).put(2);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"), HasSubstr("bad.ply: file truncated in face 1"));
  }
  {  // truncated inside a face list
    Bytes b{false, binary_head("3", "2")};
    b = tri_vertices(b);
    b.put(std::uint8_t{3}).put(0).put(1).put(2).put(std::uint8_t{3}).put(0).put(1);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"), HasSubstr("truncated in face 1"));
  }
  {  // index out of range
    Bytes b{false, binary_head("3", "2")};
    b = tri_vertices(b);
    b.put(std::uint8_t{3}).put(0).put(1).put(2).put(std::uint8_t{3}).put(0).put(1).put(3);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"),
                HasSubstr("bad.ply: face 1: vertex index 3 out of range"));
  }
  {  // negative index
    Bytes b{false, binary_head("3", "1")};
    b = tri_vertices(b);
    b.put(std::uint8_t{3}).put(0).put(-1).put(2);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"), HasSubstr("face 0: vertex index -1"));
  }
  {  // NaN coordinate
    Bytes b{false, binary_head("3", "1")};
    b = tri_vertices(b, std::numeric_limits<float>::quiet_NaN());
    b.put(std::uint8_t{3}).put(0).put(1).put(2);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"), HasSubstr("bad.ply: vertex 1 has a non-finite"));
  }
  {  // two-vertex face and negative list count
    Bytes b{false, binary_head("3", "1")};
    b = tri_vertices(b);
    b.put(std::uint8_t{2}).put(0).put(1);
    EXPECT_THAT(read_error(MeshFormat::Ply, b.data, "bad.ply"), HasSubstr("face 0 has 2 vertices"));
    Bytes c{false, binary_head("3", "1", "int")};
    c = tri_vertices(c);
    c.put(-3).put(0).put(1).put(2);
    EXPECT_THAT(read_error(MeshFormat::Ply, c.data, "bad.ply"), HasSubstr("face 0: negative list length"));
    Bytes d{false, binary_head("3", "1", "uint")};
    d = tri_vertices(d);
    d.put(std::uint32_t{4000000000u}).put(0).put(1).put(2);
    EXPECT_THAT(read_error(MeshFormat::Ply, d.data, "bad.ply"), HasSubstr("truncated in face 0"));
  }
}

TEST(StlErrors, MalformedInput) {
  const std::string facet =
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  struct Case {
    std::string data;
    std::vector<std::string> expected;
  };
  std::string binary_header(80, ' ');
  const std::vector<Case> cases = {
      {"", {"bad.stl: empty file"}},
      {"hello", {"bad.stl: not an STL file"}},
      {"solid x\n" + facet, {"bad.stl:", "missing 'endsolid'"}},
      {"solid x\n" + facet.substr(0, 40), {"bad.stl:4:", "unexpected end of file"}},
      {"solid x\nendsolid x\n", {"bad.stl: no faces"}},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 nan 0\n",
       {"bad.stl:5:", "facet 0", "non-finite"}},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
       {"bad.stl:6:", "facet 0 has 2 vertices"}},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 \x01\x02",
       {"bad.stl:5:", "binary data at line 5"}},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertx 0 0 0\n", {"bad.stl:4:", "expected 'vertex' or 'endloop'"}},
      {binary_header + std::string("\x02\x00\x00\x00", 4) + std::string(50, '\0'),
       {"bad.stl: binary STL size mismatch", "declares 2 triangles", "room for 1"}},
      {binary_header + std::string("\x00\x00\x00\x00", 4), {"bad.stl: no faces"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.data);
    const std::string msg = read_error(MeshFormat::Stl, c.data, "bad.stl");
    for (const std::string& e : c.expected) EXPECT_THAT(msg, HasSubstr(e));
  }
  Bytes b{false, binary_header};
  b.put(std::uint32_t{2});
  for (int t = 0; t < 2; ++t) {
    b.put(0.0f).put(0.0f).put(1.0f);
    b.put(0.0f).put(0.0f).put(0.0f).put(1.0f).put(0.0f).put(0.0f);
    b.put(0.0f).put(t == 1 ? std::numeric_limits<float>::infinity() : 1.0f).put(0.0f).put(std::uint16_t{0});
  }
  EXPECT_THAT(read_error(MeshFormat::Stl, b.data, "bad.stl"),
              HasSubstr("bad.stl: triangle 1: vertex 2 has a non-finite"));
}

}  // namespace
}  // namespace freeform::test

namespace freeform::test {
namespace {

// Ascii STL coordinates are read as doubles: 1e-50 is a number (0 in single precision), and a
// value beyond float's range is named as such instead of "invalid coordinate".
TEST(IoErrors, AsciiStlExtremeCoordinates) {
  const auto stl = [](const std::string& c) {
    return "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 " + c +
           "\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
  };
  const TriangleSoup tiny = read_mem(MeshFormat::Stl, stl("1e-50"), "tiny.stl");
  ASSERT_EQ(tiny.positions.size(), 3u);
  EXPECT_EQ(tiny.positions[0].z(), 0.0);
  EXPECT_THAT(read_error(MeshFormat::Stl, stl("3.5e38"), "huge.stl"),
              ::testing::HasSubstr("huge.stl:4: facet 0: coordinate '3.5e38' is beyond the single-precision range"));
  EXPECT_THAT(read_error(MeshFormat::Stl, stl("1x"), "bad.stl"), ::testing::HasSubstr("invalid coordinate"));
}

// assimp-testmodels' PLY/Wuson.ply (written by Blender 2.47) has a header line of free text
// without the 'comment' keyword: read as a comment, with a warning naming the line.
TEST(IoErrors, PlyHeaderFreeTextIsACommentWithAWarning) {
  const std::string ply =
      "ply\nformat ascii 1.0\nCreated by Blender3D 247 - www.blender.org, source file: 'wuson.blend'\n"
      "element vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
      "property list uchar uint vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  std::vector<std::string> warnings;
  const TriangleSoup soup = read_mem(MeshFormat::Ply, ply, "wuson.ply", &warnings);
  EXPECT_EQ(soup.positions.size(), 3u);
  EXPECT_EQ(soup.faces.size(), 1u);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0], ::testing::HasSubstr("wuson.ply:3: unknown PLY header line 'Created by Blender3D"));
}

}  // namespace
}  // namespace freeform::test
