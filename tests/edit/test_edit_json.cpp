// Edit-file parsing (docs/edit-format.md): every schema branch and every error message.
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/common/error.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "test_support.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "freeform/common/json_messages.h"

#include <fstream>
#include <numbers>

using namespace freeform;
using ::testing::HasSubstr;

namespace {

// An 11 x 11 grid on the unit square, spacing 0.1; vertex j*11+i at (i/10, j/10, 0).
const Mesh& grid() {
  static const Mesh mesh = Mesh::from_soup(make_plane(10, 10));
  return mesh;
}

Edit parse(const std::string& text, const std::filesystem::path& base = ".") {
  return parse_edit_text(text, grid(), "edit.json", base);
}

// The message of the error parsing `text` throws, or "" if it parses.
std::string error(const std::string& text, const std::filesystem::path& base = ".") {
  try {
    parse(text, base);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A valid edit with `extra` spliced into the top-level object.
std::string with(const std::string& extra) {
  return R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.3}}, )" + extra + "}";
}
std::string with_handle(const std::string& handle) {
  return with(R"("handles": [)" + handle + "]");
}
const std::string kRegion = R"("region": {"vertices": [60]})";

}  // namespace

TEST(EditFile, MinimalEditHasTheDefaults) {
  const Edit e = parse(R"({"support": {"vertices": [1, 2, 3]}})");
  EXPECT_EQ(e.settings.order, 2);
  EXPECT_LT(e.settings.smoothness.outer, 0);  // k - 1
  EXPECT_LT(e.settings.smoothness.inner, 0);
  EXPECT_FALSE(e.settings.anisotropic);
  EXPECT_EQ(e.deformation, Deformation::Linear);
  EXPECT_TRUE(e.multiresolution);  // the default
  EXPECT_EQ(e.support, (std::vector<Vertex>{Vertex(1), Vertex(2), Vertex(3)}));
  EXPECT_TRUE(e.handles.empty());
}

TEST(EditFile, OrderSmoothnessAndFlags) {
  const Edit e = parse(with(R"("order": 3, "smoothness": {"outer": 1.5}, "anisotropic": true, "multiresolution": true)"));
  EXPECT_EQ(e.settings.order, 3);
  EXPECT_EQ(e.settings.smoothness.outer, 1.5);
  EXPECT_LT(e.settings.smoothness.inner, 0);
  EXPECT_TRUE(e.settings.anisotropic);
  EXPECT_TRUE(e.multiresolution);
  EXPECT_FALSE(parse(with(R"("multiresolution": false)")).multiresolution);
  const Edit inner = parse(with(R"("order": 1, "smoothness": {"inner": 0})"));
  EXPECT_EQ(inner.settings.smoothness.inner, 0.0);
}

TEST(EditFile, SphereGeodesicAndVertexSelectors) {
  EXPECT_EQ(parse(R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.25}}})").support.size(), 21u);
  const Edit g = parse(R"({"support": {"geodesic": {"center": [0.52, 0.49, 0.1], "radius": 0.1001}}})");
  // From vertex (0.5, 0.5): the four grid neighbours at 0.1 and the vertex itself.
  EXPECT_EQ(g.support.size(), 5u);
  EXPECT_EQ(parse(R"({"support": {"vertices": [120, 0, 0]}})").support, (std::vector<Vertex>{Vertex(0), Vertex(120)}));
}

TEST(EditFile, SelSelectorIsRelativeToTheEditFile) {
  test::ScratchDir dir;
  std::filesystem::create_directory(dir / "sub");
  {
    std::ofstream sel(dir / "sub" / "grid.sel");
    sel << "# labels\n";
    for (int i = 0; i < 121; ++i) sel << (i < 10 ? 2 : i < 50 ? 1 : 0) << "\n";
  }
  {
    std::ofstream edit(dir / "edit.json");
    edit << R"({"support": {"sel": "sub/grid.sel", "labels": [1, 2]},
                "handles": [{"region": {"sel": "sub/grid.sel", "labels": [2]}}]})";
  }
  const Edit e = read_edit_file((dir / "edit.json").string(), grid());
  EXPECT_EQ(e.support.size(), 50u);
  ASSERT_EQ(e.handles.size(), 1u);
  EXPECT_EQ(e.handles[0].vertices.size(), 10u);
  EXPECT_THAT(error(R"({"support": {"sel": "missing.sel", "labels": [1]}})", dir.path()), HasSubstr("missing.sel"));
  EXPECT_THAT(error(R"({"support": {"sel": "sub/grid.sel"}})", dir.path()),
              HasSubstr(R"(missing required key "support.labels")"));
  EXPECT_THAT(error(R"({"support": {"sel": "sub/grid.sel", "labels": [3]}})", dir.path()),
              HasSubstr(R"("support.labels[0]" must be 0 (fixed), 1 (free) or 2 (handle), got 3)"));
  EXPECT_THAT(error(R"({"support": {"sel": "sub/grid.sel", "labels": []}})", dir.path()),
              HasSubstr("non-empty array"));
}

TEST(EditFile, HandlesAndTransforms) {
  const Edit e = parse(with(R"("handles": [
      {"region": {"vertices": [60]}, "transform": {"translate": [0, 0, 1], "rotate": {"axis": [0, 0, 2], "degrees": 90},
                                                   "scale": [1, 2, 3], "pivot": [1, 1, 1]}},
      {"region": {"vertices": [0]}, "fixed": true},
      {"region": {"vertices": [10]}},
      {"region": {"vertices": [20]}, "fixed": false, "transform": {"matrix": [[1,0,0,5],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}}])"));
  ASSERT_EQ(e.handles.size(), 4u);
  const EditHandle& h = e.handles[0];
  EXPECT_TRUE(h.movable);
  EXPECT_FALSE(h.matrix.has_value());
  EXPECT_EQ(h.manipulator.translation, Vec3(0, 0, 1));
  EXPECT_EQ(h.manipulator.scale, Vec3(1, 2, 3));
  EXPECT_EQ(*h.manipulator.pivot, Vec3(1, 1, 1));
  EXPECT_TRUE((h.manipulator.rotation.toRotationMatrix() * Vec3(1, 0, 0)).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_FALSE(e.handles[1].movable);
  // A movable handle without a transform stays where it is (identity).
  EXPECT_TRUE(e.handles[2].movable);
  EXPECT_EQ(e.handles[2].manipulator.translation, Vec3::Zero());
  EXPECT_EQ(e.handles[2].manipulator.scale, Vec3::Ones());
  EXPECT_FALSE(e.handles[2].manipulator.pivot.has_value());
  ASSERT_TRUE(e.handles[3].matrix.has_value());
  EXPECT_EQ(e.handles[3].matrix->translation(), Vec3(5, 0, 0));
}

TEST(EditFile, UnknownKeysAreNamedWithTheirPath) {
  EXPECT_THAT(error(with(R"("oder": 2)")), HasSubstr(R"(edit.json: unknown key "oder")"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transfrom": {}})")),
              HasSubstr(R"(edit.json: unknown key "handles[0].transfrom")"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"translate": [0,0,1], "rotation": {}}})")),
              HasSubstr(R"(unknown key "handles[0].transform.rotation")"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"rotate": {"axis": [0,0,1], "degrees": 9, "deg": 1}}})")),
              HasSubstr(R"(unknown key "handles[0].transform.rotate.deg")"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]], "translate": [1,0,0]}})")),
              HasSubstr(R"(unknown key "handles[0].transform.translate")"));
  EXPECT_THAT(error(R"({"support": {"sphere": {"center": [0,0,0], "radius": 1, "r": 2}}})"),
              HasSubstr(R"(unknown key "support.sphere.r")"));
  EXPECT_THAT(error(R"({"support": {"vertices": [1], "verts": [2]}})"), HasSubstr(R"(unknown key "support.verts")"));
  EXPECT_THAT(error(with(R"("smoothness": {"outer": 1, "iner": 1})")), HasSubstr(R"(unknown key "smoothness.iner")"));
  EXPECT_THAT(error(with(R"("order": 1, "order": 3)")), HasSubstr(R"(edit.json: the key "order" appears twice in one object)"));
  EXPECT_THAT(error(with_handle(R"({"region": {"vertices": [1]}, "region": {"vertices": [2]}})")),
              HasSubstr(R"(the key "region" appears twice)"));
}

TEST(EditFile, WrongTypesAndMissingKeys) {
  EXPECT_THAT(error("[1, 2]"), HasSubstr("edit.json: the edit must be a JSON object, got an array"));
  EXPECT_THAT(error(R"({"handles": []})"), HasSubstr(R"(edit.json: missing required key "support")"));
  EXPECT_THAT(error(with(R"("order": "2")")), HasSubstr(R"("order" must be an integer, got a string)"));
  EXPECT_THAT(error(with(R"("order": 2.5)")), HasSubstr(R"("order" must be an integer, got the number 2.5)"));
  EXPECT_THAT(error(with(R"("anisotropic": 1)")), HasSubstr(R"("anisotropic" must be true or false)"));
  EXPECT_THAT(error(with(R"("handles": {})")), HasSubstr(R"("handles" must be an array)"));
  EXPECT_THAT(error(with(R"("smoothness": 1)")), HasSubstr(R"("smoothness" must be an object)"));
  EXPECT_THAT(error(with(R"("smoothness": {"outer": "1"})")), HasSubstr(R"("smoothness.outer" must be a number)"));
  EXPECT_THAT(error(R"({"support": [1, 2]})"), HasSubstr(R"("support" must be an object, got an array)"));
  EXPECT_THAT(error(R"({"support": {"vertices": 3}})"), HasSubstr(R"("support.vertices" must be an array)"));
  EXPECT_THAT(error(R"({"support": {"vertices": [1, 2.5]}})"), HasSubstr(R"("support.vertices[1]" must be an integer)"));
  EXPECT_THAT(error(R"({"support": {"sphere": {"center": [0, 0], "radius": 1}}})"),
              HasSubstr(R"("support.sphere.center" must be an array of 3 numbers)"));
  EXPECT_THAT(error(R"({"support": {"sphere": {"center": [0, 0, "z"], "radius": 1}}})"),
              HasSubstr(R"("support.sphere.center[2]" must be a number)"));
  EXPECT_THAT(error(R"({"support": {"geodesic": {"center": [0, 0, 0]}}})"),
              HasSubstr(R"(missing required key "support.geodesic.radius")"));
  EXPECT_THAT(error(R"({"support": {"sel": 5, "labels": [1]}})"), HasSubstr(R"("support.sel" must be a string, got the integer 5)"));
  EXPECT_THAT(error(R"({"support": {"sel": "plane.sel\u0000.junk", "labels": [1]}})"),
              HasSubstr(R"("support.sel" contains a NUL byte)"));
  EXPECT_THAT(error(with_handle(R"({"transform": {}})")), HasSubstr(R"(missing required key "handles[0].region")"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "fixed": "yes"})")), HasSubstr(R"("handles[0].fixed" must be true or false)"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"translate": [1, 2]}})")),
              HasSubstr(R"("handles[0].transform.translate" must be an array of 3 numbers)"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0]]}})")),
              HasSubstr(R"("handles[0].transform.matrix" must be 4 rows of 4 numbers)"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"matrix": [[1,0,0,0],[0,1,0],[0,0,1,0],[0,0,0,1]]}})")),
              HasSubstr(R"("handles[0].transform.matrix[1]" must be a row of 4 numbers)"));
}

TEST(EditFile, SelectorShape) {
  EXPECT_THAT(error(R"({"support": {}})"), HasSubstr(R"("support" must have exactly one of "vertices", "sphere", "geodesic", "sel" (it has none))"));
  EXPECT_THAT(error(R"({"support": {"vertices": [1], "sphere": {"center": [0,0,0], "radius": 1}}})"), HasSubstr("(it has 2)"));
  EXPECT_THAT(error(R"({"support": {"vertices": [1], "labels": [1]}})"), HasSubstr(R"("support.labels" is only allowed together with "sel")"));
}

TEST(EditFile, EmptyOrOutOfMeshSelections) {
  EXPECT_THAT(error(R"({"support": {"vertices": []}})"), HasSubstr("edit.json: support selects no vertex (empty vertex list)"));
  EXPECT_THAT(error(R"({"support": {"sphere": {"center": [9, 9, 9], "radius": 0.5}}})"),
              HasSubstr("edit.json: support selects no vertex (no vertex within distance 0.5 of the center)"));
  EXPECT_THAT(error(with_handle(R"({"region": {"vertices": []}})")), HasSubstr("edit.json: handles[0].region selects no vertex"));
  EXPECT_THAT(error(with_handle(R"({"region": {"vertices": [121]}})")),
              HasSubstr("edit.json: handles[0].region: vertex index 121 (entry 0) is outside the mesh, which has vertices 0..120"));
  EXPECT_THAT(error(R"({"support": {"sphere": {"center": [0,0,0], "radius": 0}}})"), HasSubstr(R"("support.sphere.radius" must be > 0)"));
  EXPECT_THAT(error(R"({"support": {"geodesic": {"center": [0,0,0], "radius": -1}}})"), HasSubstr(R"("support.geodesic.radius" must be > 0)"));
}

TEST(EditFile, OrderAndSmoothnessRanges) {
  EXPECT_THAT(error(with(R"("order": 0)")), HasSubstr(R"("order" must be 1 (membrane), 2 (thin plate) or 3 (minimal curvature variation), got 0)"));
  EXPECT_THAT(error(with(R"("order": 4)")), HasSubstr("got 4"));
  EXPECT_THAT(error(with(R"("order": 2, "smoothness": {"outer": 1.5})")),
              HasSubstr(R"("smoothness.outer" must be in [0, 1] for order 2)"));
  EXPECT_THAT(error(with(R"("order": 3, "smoothness": {"inner": -0.1})")), HasSubstr(R"("smoothness.inner" must be in [0, 2])"));
  EXPECT_THAT(error(with(R"("smoothness": {"inner": 1e999})")), HasSubstr("edit.json: malformed JSON: number overflow"));
  EXPECT_EQ(error(with(R"("order": 3, "smoothness": {"outer": 2, "inner": 0})")), "");
}

TEST(EditFile, BadTransforms) {
  const auto handle = [](const std::string& t) { return with_handle("{" + kRegion + R"(, "transform": )" + t + "}"); };
  EXPECT_THAT(error(handle(R"({"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]})")),
              HasSubstr(R"("handles[0].transform.matrix": the last row must be 0 0 0 1)"));
  EXPECT_THAT(error(handle(R"({"matrix": [[1,0,0,0],[0,1,0,0],[0,0,0,0],[0,0,0,1]]})")),
              HasSubstr(R"("handles[0].transform.matrix" is singular (determinant 0))"));
  EXPECT_THAT(error(handle(R"({"matrix": [[1,2,0,0],[2,4,0,0],[0,0,1,0],[0,0,0,1]]})")), HasSubstr("is singular"));
  EXPECT_THAT(error(handle(R"({"matrix": [[0,0,0,1],[0,0,0,0],[0,0,0,0],[0,0,0,1]]})")), HasSubstr("is singular"));
  EXPECT_THAT(error(handle(R"({"scale": [1, 0, 1]})")),
              HasSubstr(R"("handles[0].transform.scale[1]" is 0: a zero scale flattens the handle (singular transform))"));
  EXPECT_THAT(error(handle(R"({"rotate": {"axis": [0, 0, 0], "degrees": 30}})")),
              HasSubstr(R"("handles[0].transform.rotate.axis" is the zero vector)"));
  EXPECT_THAT(error(handle(R"({"rotate": {"axis": [0, 0, 1]}})")),
              HasSubstr(R"(missing required key "handles[0].transform.rotate.degrees")"));
  EXPECT_THAT(error(handle(R"({"translate": [1e999, 0, 0]})")), HasSubstr("malformed JSON"));
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "fixed": true, "transform": {"translate": [0, 0, 1]}})")),
              HasSubstr(R"("handles[0]" is fixed and has a transform)"));
  // Negative scales (mirroring) are invertible and allowed.
  EXPECT_EQ(error(handle(R"({"scale": [-1, 1, 1]})")), "");
}

TEST(EditFile, MalformedJsonNamesLineAndColumn) {
  EXPECT_THAT(error("{\n  \"order\": 2,\n  \"support\": x\n}"), HasSubstr("edit.json:3: malformed JSON at column 14: syntax error"));
  EXPECT_THAT(error("{\n  \"order\": 2,\n"), HasSubstr("edit.json:3: malformed JSON at column 1"));
  EXPECT_THAT(error(""), HasSubstr("edit.json:1: malformed JSON at column 1"));
  EXPECT_THAT([] { read_edit_file("/no/such/edit.json", grid()); }, ::testing::Throws<IoError>());
}

TEST(EditFile, SelDefPair) {
  test::ScratchDir dir;
  {
    std::ofstream sel(dir / "g.sel");
    sel << "# 0 fixed, 1 free, 2 handle\n";
    for (int i = 0; i < 121; ++i) sel << (i == 60 ? 2 : i > 40 && i < 80 ? 1 : 0) << "\n";
    std::ofstream def(dir / "g.def");
    def << "# move up\n1 0 0 0\n0 1 0 0\n0 0 1 0.25\n0 0 0 1\n";
    std::ofstream bad(dir / "bad.def");
    bad << "# singular\n0 0 0 0\n0 1 0 0\n0 0 1 0.25\n0 0 0 1\n";
  }
  const Edit e = edit_from_sel_def((dir / "g.sel").string(), (dir / "g.def").string(), 3, grid());
  EXPECT_EQ(e.settings.order, 3);
  EXPECT_EQ(e.support.size(), 39u);
  ASSERT_EQ(e.handles.size(), 1u);
  EXPECT_EQ(e.handles[0].vertices, std::vector<Vertex>{Vertex(60)});
  ASSERT_TRUE(e.handles[0].matrix.has_value());
  EXPECT_EQ(e.handles[0].matrix->translation(), Vec3(0, 0, 0.25));
  EXPECT_THAT([&] { edit_from_sel_def((dir / "g.sel").string(), (dir / "bad.def").string(), 2, grid()); },
              ::testing::ThrowsMessage<InvalidInput>(HasSubstr("bad.def: the matrix is singular")));
  EXPECT_THAT([&] { edit_from_sel_def((dir / "g.sel").string(), (dir / "g.def").string(), 4, grid()); },
              ::testing::ThrowsMessage<InvalidInput>(HasSubstr("order must be 1, 2 or 3")));
}

TEST(EditFile, RegionsFromTheEdit) {
  const Edit e = parse(with(R"("handles": [{"region": {"vertices": [60]}}, {"region": {"vertices": [61]}, "fixed": true}])"));
  const Regions r = edit_regions(grid(), e);
  ASSERT_EQ(r.handles().size(), 2u);
  EXPECT_TRUE(r.handles()[0].movable);
  EXPECT_FALSE(r.handles()[1].movable);
  EXPECT_EQ(r.n_movable(), 1);
  EXPECT_EQ(r.role(Vertex(60)), Role::Handle);
}

TEST(EditFile, ExampleEditsInDataParse) {
  const auto dir = test::data_dir() / "edits";
  const Mesh plane = Mesh::from_soup(read_mesh((dir / "plane-10x10.off").string()).soup);
  int parsed = 0;
  for (const char* name : {"plane-bump.json", "plane-two-handles.json", "plane-sel.json"}) {
    const Edit e = read_edit_file((dir / name).string(), plane);
    EXPECT_FALSE(e.support.empty()) << name;
    EXPECT_FALSE(e.handles.empty()) << name;
    ++parsed;
  }
  EXPECT_EQ(parsed, 3);
  const Edit sd = edit_from_sel_def((dir / "plane.sel").string(), (dir / "plane.def").string(), 2, plane);
  EXPECT_EQ(sd.support.size(), 49u);  // the 7 x 7 block around the centre
  EXPECT_EQ(sd.handles[0].vertices.size(), 1u);
}

TEST(EditFile, ArmadilloDemoEditParses) {
  FREEFORM_REQUIRE_CGAL_MESHES();
  const Mesh mesh = Mesh::from_soup(read_mesh((test::cgal_mesh_dir() / "armadillo.off").string()).soup);
  const Edit e = read_edit_file((test::data_dir() / "edits" / "armadillo.json").string(), mesh);
  EXPECT_EQ(e.settings.order, 3);
  EXPECT_GT(e.support.size(), 500u);
  ASSERT_EQ(e.handles.size(), 1u);
  EXPECT_LT(e.handles[0].vertices.size(), e.support.size() / 4);
}

TEST(EditFile, DeformationModelKey) {
  EXPECT_EQ(parse(with(R"("deformation": "linear")")).deformation, Deformation::Linear);
  EXPECT_THAT(error(with(R"("deformation": "rigid")")),
              HasSubstr(R"(edit.json: "deformation" must be one of "linear", "nonlinear", got "rigid")"));
  EXPECT_THAT(error(with(R"("deformation": 1)")), HasSubstr(R"("deformation" must be a string)"));
  const Edit e = parse(with(R"("deformation": "nonlinear", "nonlinear": {"max_iterations": 7, "tolerance": 0.001})"));
  EXPECT_EQ(e.deformation, Deformation::Nonlinear);
  EXPECT_EQ(e.nonlinear.max_iterations, 7);
  EXPECT_EQ(e.nonlinear.tolerance, 0.001);
  EXPECT_TRUE(e.nonlinear.preserve_volume);  // the default
  EXPECT_FALSE(parse(with(R"("nonlinear": {"preserve_volume": false})")).nonlinear.preserve_volume);
  EXPECT_THAT(error(with(R"("nonlinear": {"preserve_volume": 1})")), HasSubstr(R"("nonlinear.preserve_volume" must be)"));
  Edit off = e;
  off.nonlinear.preserve_volume = false;
  test::ScratchDir dir;
  write_edit_file((dir / "nl.json").string(), off);
  const Edit back = read_edit_file((dir / "nl.json").string(), grid());
  EXPECT_EQ(back.deformation, Deformation::Nonlinear);
  EXPECT_EQ(back.nonlinear.max_iterations, 7);
  EXPECT_FALSE(back.nonlinear.preserve_volume);
  EXPECT_THAT(error(with(R"("nonlinear": {"max_iterations": 0})")),
              HasSubstr(R"("nonlinear.max_iterations" must be in [1, 100000], got 0)"));
  EXPECT_THAT(error(with(R"("nonlinear": {"tolerance": 2})")), HasSubstr(R"("nonlinear.tolerance" must be in (0, 1), got 2)"));
  EXPECT_THAT(error(with(R"("nonlinear": {"steps": 2})")), HasSubstr("steps"));
}

// Writing is the inverse of reading: every field survives, and the written edit deforms the
// mesh bit for bit like the original (manipulators with pivots become exact matrices).
TEST(EditFile, WrittenEditsReadBackAndDeformBitForBit) {
  Edit e = parse(R"({"order": 3, "smoothness": {"outer": 0.5, "inner": 1.25}, "anisotropic": false, "multiresolution": false,
                     "support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.35}},
                     "handles": [{"region": {"vertices": [60]}, "transform": {"translate": [0, 0, 0.1], "rotate": {"axis": [1, 2, 3], "degrees": 33}, "pivot": [0.4, 0.5, 0.1]}},
                                 {"region": {"vertices": [58]}, "fixed": true},
                                 {"region": {"vertices": [62]}, "transform": {"scale": [1, 2, 1], "translate": [0.01, 0.02, 0.03]}}]})");
  test::ScratchDir dir;
  const std::string path = (dir / "out.json").string();
  write_edit_file(path, e);
  const Edit back = read_edit_file(path, grid());
  EXPECT_EQ(back.settings.order, 3);
  EXPECT_EQ(back.settings.smoothness.outer, 0.5);
  EXPECT_EQ(back.settings.smoothness.inner, 1.25);
  EXPECT_FALSE(back.multiresolution);
  EXPECT_EQ(back.support, e.support);
  ASSERT_EQ(back.handles.size(), 3u);
  EXPECT_FALSE(back.handles[1].movable);
  const Mesh a = deform(grid(), e), b = deform(grid(), back);
  for (Vertex v : grid().vertices()) EXPECT_EQ(a.position(v), b.position(v)) << v.idx();
  EXPECT_NE(a.position(Vertex(60)), grid().position(Vertex(60)));  // the edit did something
}

// Hostile values get messages that name the real cause, and extreme magnitudes are handled
// without overflow or underflow (issue "hostile input").
TEST(EditFile, ExtremeMagnitudesAndHostileKeys) {
  // A rotation axis of length ~1e200 or ~3e-300 is still that direction (its norm overflows or
  // underflows), not the identity or "the zero vector".
  const auto rotation = [](const std::string& axis) {
    return parse(with_handle("{" + kRegion + R"(, "transform": {"rotate": {"axis": )" + axis + R"(, "degrees": 90}}})"))
        .handles[0]
        .manipulator.rotation;
  };
  const Eigen::Quaterniond unit = rotation("[0, 0, 1]");
  EXPECT_NEAR(unit.angularDistance(Eigen::Quaterniond::Identity()), std::numbers::pi / 2, 1e-12);
  EXPECT_LT(rotation("[0, 0, 1e200]").angularDistance(unit), 1e-12);
  EXPECT_LT(rotation("[0, 0, 3e-300]").angularDistance(unit), 1e-12);
  // A tiny scale is named with its value, not called 0.
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"scale": [1, 1e-13, 1]}})")),
              HasSubstr("\"handles[0].transform.scale[1]\" is 1e-13, at most 1e-12"));
  // A NUL byte in a key does not cut the message.
  const std::string nul_key = R"({"support": {"vertices": [1]}, "bad\u0000key": 1})";  // valid JSON: an escaped NUL
  EXPECT_THAT(error(nul_key), HasSubstr("\"bad\\u0000key\" (allowed here"));
}

TEST(EditFile, SelectorsAtExtremeScales) {
  for (const double s : {1e-200, 1e200}) {
    TriangleSoup soup = make_plane(10, 10);
    for (Vec3& p : soup.positions) p *= s;
    const Mesh mesh = Mesh::from_soup(soup);
    const auto n = [](double x) { return json_messages::num(x); };
    const Edit e = parse_edit_text(R"({"support": {"sphere": {"center": [)" + n(0.5 * s) + ", " + n(0.5 * s) +
                                       R"(, 0], "radius": )" + n(0.25 * s) + R"(}},
        "handles": [{"region": {"geodesic": {"center": [)" + n(0.5 * s) + ", " + n(0.5 * s) + ", " + n(0.001 * s) +
                                       R"(], "radius": )" + n(0.05 * s) + "}}}]}",
                                   mesh, "edit.json", ".");
    EXPECT_EQ(e.support.size(), 21u) << s;  // 1 + 4 + 4 + 4 + 8: grid points within 2.5 spacings
    EXPECT_EQ(e.handles[0].vertices, std::vector<Vertex>{Vertex(60)}) << s;
  }
}

TEST(EditFile, OverflowingTransformsAreNamedAsSuch) {
  const Edit e = parse(with_handle("{" + kRegion + R"(, "transform": {"translate": [1e308, 1e308, 0]}})"));
  try {
    Mesh out = deform(grid(), e);
    ADD_FAILURE() << "expected an error";
  } catch (const InvalidInput& ex) {
    EXPECT_THAT(ex.what(), HasSubstr("too large for double precision"));
  }
  // A matrix scaled by 1e300 is invertible; only its determinant overflows: not "singular".
  EXPECT_THAT(error(with_handle("{" + kRegion + R"(, "transform": {"matrix": [[1e300,0,0,0],[0,1e300,0,0],[0,0,1e300,0],[0,0,0,1]]}})")),
              HasSubstr(R"("handles[0].transform.matrix" is too large for double precision (its determinant overflows))"));
}
