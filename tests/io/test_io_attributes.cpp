// What a file holds besides positions and triangles (OBJ, OFF, and between formats): kept on
// reading, written back with only positions and normals changed; real files from Debian's
// assimp-testmodels and generated ones with seams, quads and n-gons.
#include "io_test_util.h"

#include <filesystem>
#include <sstream>

namespace freeform::test {
namespace {

namespace fs = std::filesystem;

const fs::path kAssimp = "/usr/share/assimp/models";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

std::vector<Vec3> moved(const std::vector<Vec3>& positions) {
  std::vector<Vec3> out;
  for (const Vec3& p : positions) out.push_back(Eigen::AngleAxisd(0.5, Vec3(0, 0, 1)) * p * 2.0 + Vec3(1, 2, 3));
  return out;
}

std::string rewrite(const ReadResult& file, std::span<const Vec3> positions, const std::string& path,
                    std::vector<std::string>* dropped = nullptr) {
  MeshBytes bytes = mesh_bytes(path, file, positions);
  if (dropped) *dropped = bytes.dropped;
  return bytes.data;
}

// A textured quad strip with a UV seam, an n-gon, groups, a material and smoothing groups.
const std::string kTexturedObj =
    "# made by hand\n"
    "mtllib strip.mtl\n"
    "o strip\n"
    "v 0 0 0\nv 1 0 0\nv 2 0 0.0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 3 0.5 0\n"
    "vt 0 0\nvt 0.5 0\nvt 1 0\nvt 0 1\nvt 0.5 1\nvt 1 1\nvt 0.25 0.25\n"
    "vn 0 0 1\nvn 0 0 1\n"
    "g left\nusemtl red\ns 1\n"
    "f 1/1/1 2/2/1 5/5/1 4/4/1\n"
    "g right\nusemtl blue\ns off\n"
    "f 2/7/2 3/3/2 7/3/2 6/6/2 5/5/2   # a pentagon\n";

TEST(ObjAttributes, KeepsPolygonsSeamsAndNormals) {
  const ReadResult r = read_file_mem(MeshFormat::Obj, kTexturedObj, "strip.obj");
  ASSERT_EQ(r.attributes.polygons.size(), 2);
  EXPECT_EQ(r.attributes.polygons.corner_count(0), 4);
  EXPECT_EQ(r.attributes.polygons.corner_count(1), 5);
  EXPECT_EQ(r.soup.faces.size(), 5u);
  EXPECT_THAT(r.attributes.triangle_polygon, ::testing::ElementsAre(0, 0, 1, 1, 1));
  ASSERT_FALSE(r.attributes.uv.empty());
  // Vertex 2 (index 1) has uv row 1 in the quad and row 6 in the pentagon: a seam kept.
  EXPECT_EQ(r.attributes.uv.index[1], 1);
  EXPECT_EQ(r.attributes.uv.index[4], 6);
  EXPECT_EQ(r.attributes.normal.rows(), 2);
  EXPECT_FALSE(per_vertex_values(r.attributes.polygons, r.attributes.uv, 7).has_value());
}

TEST(ObjAttributes, RewriteChangesOnlyPositionsAndNormals) {
  const ReadResult r = read_file_mem(MeshFormat::Obj, kTexturedObj, "strip.obj");
  ASSERT_TRUE(r.source);
  EXPECT_EQ(rewrite(r, r.soup.positions, "out.obj"), kTexturedObj);  // unchanged: byte for byte
  // Lift vertex 7 (only in the pentagon): its normal row 1 is recomputed, row 0 kept as written.
  std::vector<Vec3> p = r.soup.positions;
  p[6].z() = 1.0;
  const std::vector<std::string> in = lines_of(kTexturedObj), out = lines_of(rewrite(r, p, "out.obj"));
  ASSERT_EQ(in.size(), out.size());
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i] == "v 3 0.5 0") {
      EXPECT_EQ(out[i], "v 3 0.5 1");
    } else if (i > 0 && in[i] == "vn 0 0 1" && in[i - 1] == "vn 0 0 1") {
      EXPECT_NE(out[i], in[i]);  // the pentagon's normal row tilts
    } else {
      EXPECT_EQ(out[i], in[i]) << "line " << i + 1;
    }
  }
  const ReadResult back = read_file_mem(MeshFormat::Obj, rewrite(r, p, "out.obj"), "out.obj");
  // The pentagon (1,0,0) (2,0,0) (3,.5,1) (2,1,0) (1,1,0): Newell's normal, normalized.
  Vec3 area = Vec3::Zero();
  const int pent[5] = {1, 2, 6, 5, 4};
  for (int i = 0; i < 5; ++i) area += p[static_cast<std::size_t>(pent[i])].cross(p[static_cast<std::size_t>(pent[(i + 1) % 5])]);
  const Vec3 n(back.attributes.normal.values[3], back.attributes.normal.values[4], back.attributes.normal.values[5]);
  EXPECT_LT((n - area.normalized()).norm(), 1e-12);
  EXPECT_EQ(back.attributes.uv.values, r.attributes.uv.values);
  EXPECT_EQ(back.attributes.uv.index, r.attributes.uv.index);
}

TEST(ObjAttributes, VertexColours) {
  const std::string obj = "v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n";
  const ReadResult r = read_file_mem(MeshFormat::Obj, obj, "c.obj");
  const NamedAttribute* color = r.attributes.vertex_attribute("color");
  ASSERT_NE(color, nullptr);
  EXPECT_EQ(color->width, 3);
  EXPECT_EQ(color->values, (std::vector<double>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
  std::vector<Vec3> p = r.soup.positions;
  p[0].x() = -1;
  EXPECT_EQ(rewrite(r, p, "o.obj"), "v -1 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
}

// `vn` rows that no face uses are not the mesh's normals: a rewrite keeps them as written.
TEST(ObjAttributes, NormalsNoFaceUsesAreKept) {
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1 2 3\n";
  const ReadResult r = read_file_mem(MeshFormat::Obj, obj, "n.obj");
  EXPECT_TRUE(r.attributes.normal.empty());
  std::vector<Vec3> p = r.soup.positions;
  p[2].z() = 1;
  EXPECT_EQ(rewrite(r, p, "o.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 1\nvn 0 0 1\nf 1 2 3\n");
}

TEST(ObjAttributes, ForwardTextureIndexOutOfRangeNamesTheFace) {
  EXPECT_THAT(read_error(MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/9\n", "t.obj"),
              ::testing::HasSubstr("t.obj:5: face 0: texture coordinate index 9 out of range (file has 1 texture coordinates)"));
  EXPECT_THAT(read_error(MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//-2 2//1 3//1\n", "n.obj"),
              ::testing::HasSubstr("relative normal index -2 reaches before the first normal"));
}

TEST(OffAttributes, ColoursNormalsAndPolygons) {
  const std::string off =
      "NCOFF\n5 2 0\n"
      "0 0 0  0 0 1  255 0 0 255\n1 0 0  0 0 1  0 255 0 255\n1 1 0  0 0 1  0 0 255 255\n0 1 0  0 0 1  9 9 9 255\n"
      "2 2 0  0 0 1  1 2 3 4\n"
      "4 0 1 2 3  0.5 0.5 0.5\n3 1 4 2  0.1 0.2 0.3\n";
  // The keyword order is [ST][C][N]: "NCOFF" is not an OFF keyword.
  EXPECT_THAT(read_error(MeshFormat::Off, off, "a.off"), ::testing::HasSubstr("missing OFF header"));
  const std::string good = "CN" + off.substr(2);
  const ReadResult r = read_file_mem(MeshFormat::Off, good, "a.off");
  EXPECT_EQ(r.attributes.polygons.size(), 2);
  const NamedAttribute* color = r.attributes.vertex_attribute("color");
  ASSERT_NE(color, nullptr);
  EXPECT_EQ(color->width, 4);
  EXPECT_DOUBLE_EQ(color->values[0], 1.0);
  ASSERT_EQ(r.attributes.face.size(), 1u);
  EXPECT_EQ(r.attributes.face[0].width, 3);
  EXPECT_EQ(r.attributes.normal.rows(), 5);
  EXPECT_EQ(rewrite(r, r.soup.positions, "b.off"), good);
  const ReadResult back = read_file_mem(MeshFormat::Off, rewrite(r, moved(r.soup.positions), "b.off"), "b.off");
  EXPECT_EQ(back.attributes.vertex_attribute("color")->values, color->values);
  const Vec3 n(back.attributes.normal.values[0], back.attributes.normal.values[1], back.attributes.normal.values[2]);
  EXPECT_LT((n - Vec3(0, 0, 1)).norm(), 1e-12);  // rotated about z: still +z
  EXPECT_LT((back.soup.positions[4] - moved(r.soup.positions)[4]).norm(), 1e-15);
}

TEST(OffAttributes, DeclaredValuesMissingIsAnError) {
  EXPECT_THAT(read_error(MeshFormat::Off, "COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0\n0 1 0 1 1 1\n3 0 1 2\n", "c.off"),
              ::testing::HasSubstr("c.off:4: vertex 1 has 0 values after its coordinates"));
}

TEST(ConvertAttributes, WhatEachFormatCanHold) {
  const ReadResult r = read_file_mem(MeshFormat::Obj, kTexturedObj, "strip.obj");
  std::vector<std::string> dropped;
  // OFF and PLY store one texture coordinate per vertex: the seam cannot be kept.
  const ReadResult off = read_file_mem(MeshFormat::Off, rewrite(r, r.soup.positions, "x.off", &dropped), "x.off");
  EXPECT_THAT(dropped, ::testing::Contains(::testing::HasSubstr("texture coordinates with seams")));
  EXPECT_THAT(dropped, ::testing::Contains(::testing::HasSubstr("groups")));
  EXPECT_EQ(off.attributes.polygons.corners, r.attributes.polygons.corners);
  EXPECT_TRUE(off.attributes.uv.empty());
  rewrite(r, r.soup.positions, "x.stl", &dropped);
  EXPECT_THAT(dropped, ::testing::Contains(::testing::HasSubstr("polygons (STL holds triangles)")));
  // OBJ from OFF: colours, polygons and normals come through.
  const std::string coff = "COFF\n4 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n0 1 0 1 1 1\n4 0 1 2 3\n";
  const ReadResult c = read_file_mem(MeshFormat::Off, coff, "c.off");
  const ReadResult obj = read_file_mem(MeshFormat::Obj, rewrite(c, c.soup.positions, "c.obj", &dropped), "c.obj");
  EXPECT_TRUE(dropped.empty());
  EXPECT_EQ(obj.attributes.polygons.corner_count(0), 4);
  EXPECT_EQ(obj.attributes.vertex_attribute("color")->values, c.attributes.vertex_attribute("color")->values);
}

// Every OBJ of assimp-testmodels that is a mesh: rewritten unchanged, byte for byte; moved, only
// `v` and `vn` lines differ and the positions read back.
TEST(ObjAttributes, AssimpTestModelsRoundTrip) {
  const fs::path dir = kAssimp / "OBJ";
  if (!fs::exists(dir)) GTEST_SKIP() << "assimp-testmodels not installed";
  int checked = 0;
  for (const char* name : {"spider.obj", "WusonOBJ.obj", "box.obj", "concave_polygon.obj", "cube_usemtl.obj",
                           "cube_with_vertexcolors.obj", "empty_mat.obj", "regr01.obj", "testmixed.obj"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    const std::string data = read_file(path);
    const ReadResult r = read_mesh(path);
    ASSERT_TRUE(r.source);
    const std::string beside = (dir / "o.obj").string();  // in its folder: material libraries as named
    EXPECT_EQ(rewrite(r, r.soup.positions, beside), data);
    const std::vector<Vec3> p = moved(r.soup.positions);
    const std::string out = rewrite(r, p, beside);
    const std::vector<std::string> a = lines_of(data), b = lines_of(out);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].rfind("v ", 0) != 0 && a[i].rfind("vn ", 0) != 0) {
        ASSERT_EQ(a[i], b[i]) << "line " << i + 1;
      }
    const ReadResult back = read_file_mem(MeshFormat::Obj, out, "o.obj");
    for (std::size_t v = 0; v < p.size(); ++v) ASSERT_EQ(back.soup.positions[v], p[v]);
    EXPECT_EQ(back.attributes.uv.values, r.attributes.uv.values);
    for (int row = 0; row < back.attributes.normal.rows(); ++row) {
      const double* n = &back.attributes.normal.values[static_cast<std::size_t>(row) * 3];
      const double length = Vec3(n[0], n[1], n[2]).norm();
      if (length != 0) {
        EXPECT_NEAR(length, 1.0, 1e-9);  // a normal no face uses keeps the file's (zero) value
      }
    }
    ++checked;
  }
  EXPECT_EQ(checked, 9);
}

TEST(ObjAttributes, RecomputedNormalsOfARotatedCubeAreTheRotatedFaceNormals) {
  const fs::path path = kAssimp / "OBJ" / "cube_usemtl.obj";
  if (!fs::exists(path)) GTEST_SKIP() << "assimp-testmodels not installed";
  // A cube with one normal per face (6 vn): the recomputed normals of the rotated cube are the
  // rotated file normals, up to sign conventions of the file (checked: same direction).
  const ReadResult r = read_mesh(path.string());
  ASSERT_EQ(r.attributes.normal.rows(), 6);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Vec3> p;
  for (const Vec3& x : r.soup.positions) p.push_back(rot * x);
  const std::vector<double> n = recomputed_normals(r.attributes.polygons, r.attributes.normal, p, r.soup.positions);
  for (int row = 0; row < 6; ++row) {
    const Vec3 file(&r.attributes.normal.values[static_cast<std::size_t>(row) * 3]);
    const Vec3 now(&n[static_cast<std::size_t>(row) * 3]);
    EXPECT_LT((now - rot * file.normalized()).norm(), 1e-12) << "row " << row;
  }
}

}  // namespace
}  // namespace freeform::test
