// A repaired file keeps what it held (io/repair.h): polygons, texture coordinates, colours and
// face properties follow the split vertices and the dropped faces, and the repaired file reads
// back as a manifold mesh with them.
#include "io_test_util.h"

#include "freeform/io/repair.h"
#include "freeform/mesh/mesh.h"

#include <algorithm>
#include <filesystem>
#include <random>
#include <string>

namespace freeform::test {
namespace {

namespace fs = std::filesystem;

// A quad and a triangle that touch only at vertex 3 (two fans: a non-manifold vertex), and a
// triangle that repeats a vertex; texture coordinates on every corner.
const std::string kBowtieObj =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 2 0\nv 1 2 0\n"
    "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\nvt 1 1\nvt 0.5 1\nvt 0.9 0.9\n"
    "g body\n"
    "f 1/1 2/2 3/3 4/4\n"
    "f 3/7 5/5 6/6\n"
    "f 4/4 4/4 1/1\n";

bool polygon_holds(const Polygons& p, int polygon, const Tri& face) {
  const auto begin = p.corners.begin() + p.offsets[static_cast<std::size_t>(polygon)];
  const auto end = p.corners.begin() + p.offsets[static_cast<std::size_t>(polygon) + 1];
  return std::all_of(face.begin(), face.end(), [&](int v) { return std::find(begin, end, v) != end; });
}

TEST(Repair, ObjKeepsPolygonsAndTextureCoordinates) {
  ReadResult r = read_file_mem(MeshFormat::Obj, kBowtieObj, "bowtie.obj");
  ASSERT_THROW(Mesh::from_soup(r.soup), TopologyError);
  const std::vector<int> uv_before = r.attributes.uv.index;
  std::string lost;
  const BuildReport report = repair(r, "test.obj", lost);
  EXPECT_EQ(report.split_vertices, 1);
  EXPECT_EQ(report.dropped_faces, 1);
  EXPECT_THAT(lost, ::testing::HasSubstr("groups are not kept"));  // only a rewrite keeps them
  ASSERT_EQ(r.soup.positions.size(), 7u);  // vertex 3's second fan got vertex 7
  EXPECT_EQ(r.soup.positions[6], r.soup.positions[2]);
  ASSERT_EQ(r.attributes.polygons.size(), 2);  // the degenerate triangle's polygon is gone
  EXPECT_EQ(r.attributes.polygons.corner_count(0), 4);
  // Exactly one of the two polygons now uses the copy at its corner on vertex 3.
  const int quad_corner = r.attributes.polygons.corners[2], triangle_corner = r.attributes.polygons.corners[4];
  EXPECT_NE(quad_corner, triangle_corner);
  EXPECT_TRUE((quad_corner == 2 && triangle_corner == 6) || (quad_corner == 6 && triangle_corner == 2));
  // Each corner keeps its texture coordinate; the dropped polygon's three corners are gone.
  EXPECT_EQ(r.attributes.uv.index, std::vector<int>(uv_before.begin(), uv_before.begin() + 7));
  ASSERT_EQ(r.attributes.triangle_polygon.size(), r.soup.faces.size());
  for (std::size_t f = 0; f < r.soup.faces.size(); ++f)
    EXPECT_TRUE(polygon_holds(r.attributes.polygons, r.attributes.triangle_polygon[f], r.soup.faces[f])) << f;

  // Written anew and read back: a manifold mesh with the same polygons and texture coordinates.
  const MeshBytes bytes = mesh_bytes("fixed.obj", r, r.soup.positions);
  const ReadResult back = read_file_mem(MeshFormat::Obj, bytes.data, "fixed.obj");
  EXPECT_NO_THROW(Mesh::from_soup(back.soup));
  EXPECT_EQ(back.soup.positions.size(), 7u);
  EXPECT_EQ(back.attributes.polygons.corners, r.attributes.polygons.corners);
  ASSERT_FALSE(back.attributes.uv.empty());
  for (std::size_t c = 0; c < back.attributes.uv.index.size(); ++c)
    for (int k = 0; k < 2; ++k)
      EXPECT_EQ(back.attributes.uv.values[2 * static_cast<std::size_t>(back.attributes.uv.index[c]) + k],
                r.attributes.uv.values[2 * static_cast<std::size_t>(r.attributes.uv.index[c]) + k]);
}

TEST(Repair, PlyCopiesColoursAndDropsTheFacePropertiesOfDroppedFaces) {
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "element face 3\nproperty list uchar int vertex_indices\nproperty uchar flag\nend_header\n"
      "0 0 0 255 0 0\n1 0 0 0 255 0\n0.5 1 0 0 0 255\n0 2 0 255 255 0\n1 2 0 0 255 255\n"
      "3 0 1 2 7\n3 2 4 3 8\n3 3 3 4 9\n";
  ReadResult r = read_file_mem(MeshFormat::Ply, ply, "bowtie.ply");
  std::string lost;
  const BuildReport report = repair(r, "test.obj", lost);
  EXPECT_EQ(report.added_vertices, 1);
  const NamedAttribute* colour = r.attributes.vertex_attribute("color");
  ASSERT_NE(colour, nullptr);
  ASSERT_EQ(colour->values.size(), 6u * static_cast<std::size_t>(colour->width));
  for (int c = 0; c < colour->width; ++c)  // the copy of vertex 2 is blue like it
    EXPECT_EQ(colour->values[static_cast<std::size_t>(5 * colour->width + c)],
              colour->values[static_cast<std::size_t>(2 * colour->width + c)]);
  const auto flag = std::find_if(r.attributes.face.begin(), r.attributes.face.end(),
                                 [](const NamedAttribute& a) { return a.name == "flag"; });
  ASSERT_NE(flag, r.attributes.face.end());
  EXPECT_EQ(flag->values, (std::vector<double>{7, 8}));
}

// A polygon the repair cannot keep whole: a quad that repeats a vertex (its degenerate triangle
// dropped), and assimp-testmodels' concave 66-gon, whose fan overlaps itself; each becomes its
// triangles, which read back as a manifold mesh with each corner's attributes.
TEST(Repair, PolygonsThatCannotStayWholeBecomeTheirTriangles) {
  ReadResult r = read_file_mem(MeshFormat::Obj,
                               "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                               "f 1/1 2/2 2/2 3/3\nf 1/1 3/3 4/4\n",
                               "repeats.obj");
  std::string lost;
  EXPECT_EQ(repair(r, "test.obj", lost).dropped_faces, 1);
  ASSERT_EQ(r.attributes.polygons.size(), 2);
  EXPECT_EQ(r.attributes.polygons.corner_count(0), 3);
  EXPECT_EQ(r.attributes.uv.index, (std::vector<int>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(r.attributes.triangle_polygon, (std::vector<int>{0, 1}));

  const fs::path concave = "/usr/share/assimp/models/OBJ/concave_polygon.obj";
  if (!fs::exists(concave)) {
    if (data_required()) FAIL() << concave << " missing: apt-get install assimp-testmodels";
    GTEST_SKIP() << "assimp-testmodels not installed";
  }
  ReadResult file = read_mesh(concave.string());
  ASSERT_EQ(file.attributes.polygons.size(), 1);
  ASSERT_THROW(Mesh::from_soup(file.soup), TopologyError);
  EXPECT_GT(repair(file, concave.string(), lost).split_vertices, 0);
  EXPECT_EQ(file.attributes.polygons.size(), static_cast<int>(file.soup.faces.size()));
  const ReadResult back =
      read_file_mem(MeshFormat::Obj, mesh_bytes("fixed.obj", file, file.soup.positions).data, "fixed.obj");
  EXPECT_NO_THROW(Mesh::from_soup(back.soup));
  EXPECT_EQ(back.attributes.polygons.size(), file.attributes.polygons.size());
  EXPECT_EQ(back.attributes.normal.index.size(), back.attributes.polygons.corners.size());
}

// Random polygon soups over a few vertices (repeated corners, fans meeting at vertices and
// edges, texture coordinates on every corner): a repaired file reads back as a manifold mesh,
// with an attribute row for every corner and a polygon for every triangle; or the repair
// refuses with an Error (e.g. every face dropped), never anything else.
TEST(Repair, RandomSoupsReadBackManifoldWithTheirAttributes) {
  std::mt19937 rng(43);
  int repaired = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int n = std::uniform_int_distribution<int>(3, 9)(rng);
    std::string obj;
    for (int v = 0; v < n; ++v)
      obj += "v " + std::to_string(v % 3) + " " + std::to_string(v / 3) + " " + std::to_string(v % 2) + "\nvt 0." +
             std::to_string(v) + " 0.5\n";
    const int faces = std::uniform_int_distribution<int>(1, 12)(rng);
    for (int f = 0; f < faces; ++f) {
      obj += "f";
      const int corners = std::uniform_int_distribution<int>(3, 5)(rng);
      for (int c = 0; c < corners; ++c) {
        const int v = std::uniform_int_distribution<int>(1, n)(rng);
        obj += " " + std::to_string(v) + "/" + std::to_string(v);
      }
      obj += "\n";
    }
    ReadResult r = read_file_mem(MeshFormat::Obj, obj, "random.obj");
    std::string lost;
    try {
      repair(r, "test.obj", lost);
    } catch (const Error&) {
      continue;
    }
    ++repaired;
    ASSERT_EQ(r.attributes.uv.index.size(), r.attributes.polygons.corners.size()) << obj;
    ASSERT_EQ(r.attributes.triangle_polygon.size(), r.soup.faces.size()) << obj;
    const ReadResult back =
        read_file_mem(MeshFormat::Obj, mesh_bytes("fixed.obj", r, r.soup.positions).data, "fixed.obj");
    EXPECT_NO_THROW(Mesh::from_soup(back.soup)) << obj;
    EXPECT_EQ(back.soup.faces.size(), r.soup.faces.size()) << obj;
  }
  EXPECT_GT(repaired, 300);
}

TEST(Repair, RefusesToLeaveNoFace) {
  ReadResult r = read_file_mem(MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nf 1 1 2\nf 2 2 1\n", "flat.obj");
  std::string lost;
  try {
    repair(r, "flat.obj", lost);
    ADD_FAILURE() << "a repair left no face";
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr("flat.obj: every face repeats a vertex"));
  }
}

// STL and glTF store floats and weld corners at equal positions on reading: a repaired file's
// split copies, and points apart by less than a float's precision, come back joined. Writing
// says so, and the count is what their readers actually join.
TEST(Repair, FormatsThatJoinEqualPositionsSayTheSplitIsLost) {
  ReadResult r = read_file_mem(MeshFormat::Obj, kBowtieObj, "bowtie.obj");
  std::string lost;
  repair(r, "bowtie.obj", lost);
  for (const char* path : {"fixed.stl", "fixed.glb"}) {
    const MeshBytes bytes = mesh_bytes(path, r, r.soup.positions);
    EXPECT_THAT(bytes.dropped, ::testing::Contains(::testing::HasSubstr("separate vertices at equal positions: 1 ")))
        << path;
    const ReadResult back = read_file_mem(format_from_path(path), bytes.data, path);
    EXPECT_EQ(back.soup.positions.size(), r.soup.positions.size() - 1) << path;
    EXPECT_THROW(Mesh::from_soup(back.soup), TopologyError) << path;
  }
  for (const char* path : {"fixed.obj", "fixed.off", "fixed.ply"}) {
    const MeshBytes bytes = mesh_bytes(path, r, r.soup.positions);
    EXPECT_THAT(bytes.dropped, ::testing::Not(::testing::Contains(::testing::HasSubstr("equal positions")))) << path;
  }
  // Apart as doubles, one float: joined too. Moved apart by a deformation: kept.
  std::vector<Vec3> moved = r.soup.positions;
  moved[6] += Vec3(1e-12, 0.0, 0.0);
  EXPECT_THAT(mesh_bytes("a.stl", r, moved).dropped, ::testing::Contains(::testing::HasSubstr("positions: 1 ")));
  moved[6] += Vec3(1e-3, 0.0, 0.0);
  EXPECT_THAT(mesh_bytes("a.stl", r, moved).dropped,
              ::testing::Not(::testing::Contains(::testing::HasSubstr("equal positions"))));
  EXPECT_EQ(read_file_mem(MeshFormat::Stl, mesh_bytes("a.stl", r, moved).data, "a.stl").soup.positions.size(), 7u);
}

TEST(Repair, ManifoldFileIsUntouched) {
  ReadResult r = read_file_mem(MeshFormat::Obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n", "tri.obj");
  const auto source = r.source;
  std::string lost = "stale";
  EXPECT_FALSE(repair(r, "test.obj", lost).changed());
  EXPECT_TRUE(lost.empty());
  EXPECT_EQ(r.source, source);  // still written back byte for byte
  EXPECT_EQ(r.soup.positions.size(), 3u);
}

}  // namespace
}  // namespace freeform::test
