// End-to-end tests of the `freeform` executable: output, exit codes, no partial files.
#include "cli/cli_runner.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <fstream>

using namespace freeform;
using ::testing::HasSubstr;
using namespace freeform::test;

namespace {

const char* kTetraObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

}  // namespace

TEST(Cli, InfoJsonHasCountsAndTopology) {
  test::ScratchDir dir;
  write_text(dir / "tetra.obj", kTetraObj);
  const CliRun r = freeform_cli("info --json " + q(dir / "tetra.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["vertices"], 4);
  EXPECT_EQ(j["faces"], 4);
  EXPECT_EQ(j["edges"], 6);
  EXPECT_EQ(j["genus"], 0);
  EXPECT_EQ(j["euler_characteristic"], 2);
  EXPECT_EQ(j["boundary_loops"], 0);
  EXPECT_EQ(j["components"], 1);
  EXPECT_EQ(j["manifold"], true);
  EXPECT_EQ(j["bounding_box"]["max"], nlohmann::json({1.0, 1.0, 1.0}));
  // Edges: three of length 1 and three of length sqrt(2).
  EXPECT_NEAR(j["mean_edge_length"].get<double>(), (3 + 3 * std::sqrt(2.0)) / 6, 1e-12);
  EXPECT_EQ(j["attributes"], nlohmann::json::parse(
                                 R"({"format": "obj", "polygons": 4, "texture_coordinates": 0, "normals": 0,
                                     "vertex": [], "face": []})"));
}

TEST(Cli, InfoNamesWhatTheFileHolds) {
  test::ScratchDir dir;
  write_text(dir / "quad.off", "COFF\n4 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n0 1 0 1 1 1\n4 0 1 2 3\n");
  const CliRun r = freeform_cli("info " + q(dir / "quad.off"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, ::testing::HasSubstr("polygons              1\n"));
  EXPECT_THAT(r.out, ::testing::HasSubstr("vertex attributes     [\"color\"]"));
}

TEST(Cli, InfoReportsDefectsWithoutRefusing) {
  test::ScratchDir dir;
  // Bowtie at vertex 3, plus an unreferenced duplicate of vertex 1.
  write_text(dir / "bowtie.obj", "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0 2 0\nv 1 2 0\nv 1 0 0\nf 1 2 3\nf 3 5 4\n");
  const CliRun r = freeform_cli("info --json " + q(dir / "bowtie.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["manifold"], false);
  EXPECT_EQ(j["nonmanifold_vertices"], 1);
  EXPECT_EQ(j["details"]["nonmanifold_vertices"], nlohmann::json({2}));
  EXPECT_EQ(j["duplicate_vertices"], 1);
  EXPECT_EQ(j["unreferenced_vertices"], 1);
  EXPECT_EQ(j["components"], 2);
}

TEST(Cli, InfoTextMentionsCounts) {
  test::ScratchDir dir;
  write_text(dir / "tetra.obj", kTetraObj);
  const CliRun r = freeform_cli("info " + q(dir / "tetra.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("vertices              4"));
  EXPECT_THAT(r.out, HasSubstr("genus                 0"));
}

TEST(Cli, BadInputExitsOneNamingTheFile) {
  test::ScratchDir dir;
  write_text(dir / "broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  CliRun r = freeform_cli("info " + q(dir / "broken.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("broken.obj:4"));
  r = freeform_cli("info " + q(dir / "missing.off"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("missing.off"));
}

TEST(Cli, UsageErrorsExitTwo) {
  EXPECT_EQ(freeform_cli("").exit_code, 2);
  EXPECT_EQ(freeform_cli("info").exit_code, 2);
  EXPECT_EQ(freeform_cli("info a.obj --no-such-flag").exit_code, 2);
  EXPECT_EQ(freeform_cli("frobnicate").exit_code, 2);
  const CliRun help = freeform_cli("convert --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_THAT(help.out, HasSubstr("Exit codes"));
}

TEST(Cli, ConvertRoundTripsThroughEveryFormat) {
  test::ScratchDir dir;
  write_text(dir / "tetra.obj", kTetraObj);
  for (const char* ext : {"off", "ply", "stl", "obj", "gltf", "glb"}) {
    const auto out = dir / (std::string("t.") + ext);
    const CliRun r = freeform_cli("convert " + q(dir / "tetra.obj") + " " + q(out));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const ReadResult back = read_mesh(out.string());
    EXPECT_EQ(back.soup.positions.size(), 4u) << ext;
    EXPECT_EQ(back.soup.faces.size(), 4u) << ext;
  }
}

// A coloured quad: OBJ keeps the polygon and the colours (silently); STL drops both and says so;
// in its own format the file comes back byte for byte.
TEST(Cli, ConvertKeepsWhatBothFormatsHold) {
  test::ScratchDir dir;
  const std::string coff = "COFF\n# a quad\n4 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n0 1 0 1 1 1\n4 0 1 2 3\n";
  write_text(dir / "quad.off", coff);
  CliRun r = freeform_cli("convert " + q(dir / "quad.off") + " " + q(dir / "quad.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err, "warning: 1 polygon with more than 3 vertices fan-triangulated into 2 triangles\n");
  const ReadResult obj = read_mesh((dir / "quad.obj").string());
  EXPECT_EQ(obj.attributes.polygons.size(), 1);
  ASSERT_NE(obj.attributes.vertex_attribute("color"), nullptr);
  EXPECT_EQ(obj.attributes.vertex_attribute("color")->values[4], 1.0);  // vertex 1 is green
  r = freeform_cli("convert " + q(dir / "quad.off") + " " + q(dir / "quad.stl"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("note: " + (dir / "quad.stl").string() + " cannot hold the input's polygons (STL holds triangles)"));
  EXPECT_THAT(r.err, HasSubstr("cannot hold the input's vertex property 'color'"));
  r = freeform_cli("convert " + q(dir / "quad.off") + " " + q(dir / "copy.off"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(slurp(dir / "copy.off"), coff);
}

TEST(Cli, ConvertLeavesNothingOnFailure) {
  test::ScratchDir dir;
  write_text(dir / "broken.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  CliRun r = freeform_cli("convert " + q(dir / "broken.off") + " " + q(dir / "out.ply"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "out.ply"));

  write_text(dir / "tetra.obj", kTetraObj);
  r = freeform_cli("convert " + q(dir / "tetra.obj") + " " + q(dir / "no-such-dir" / "out.ply"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_THAT(r.err, HasSubstr("no-such-dir"));
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, 2u);  // only the two inputs
}

TEST(Cli, ConvertRefusesToOverwriteItsInput) {
  test::ScratchDir dir;
  write_text(dir / "tetra.obj", kTetraObj);
  const CliRun r = freeform_cli("convert " + q(dir / "tetra.obj") + " " + q(dir / "tetra.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("--overwrite-input"));
  EXPECT_EQ(slurp(dir / "tetra.obj"), kTetraObj);
  EXPECT_EQ(freeform_cli("convert --overwrite-input " + q(dir / "tetra.obj") + " " + q(dir / "tetra.obj")).exit_code, 0);
}

TEST(Cli, ConvertRepairSplitsNonManifoldVertices) {
  test::ScratchDir dir;
  write_text(dir / "bowtie.obj", "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0 2 0\nv 1 2 0\nf 1 2 3\nf 3 5 4\n");
  const CliRun r = freeform_cli("convert --repair " + q(dir / "bowtie.obj") + " " + q(dir / "fixed.off"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("split vertex 2"));
  EXPECT_EQ(read_mesh((dir / "fixed.off").string()).soup.positions.size(), 6u);
}

// A real file's kind of defect (a vertex where two fans meet): deform names the file and the
// repair, and the repaired copy keeps the polygons and texture coordinates (io/repair.h).
TEST(Cli, RepairedCopyKeepsTextureCoordinates) {
  test::ScratchDir dir;
  write_text(dir / "bowtie.obj",
             "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0 2 0\nv 1 2 0\nvt 0 0\nvt 1 0\nvt 0.5 1\nvt 0.2 0.8\n"
             "f 1/1 2/2 3/3\nf 3/4 5/2 4/1\n");
  const CliRun refused =
      freeform_cli("deform " + q(dir / "bowtie.obj") + " --sel x.sel --def x.def -o " + q(dir / "out.obj"));
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_THAT(refused.err, HasSubstr("bowtie.obj: mesh is not manifold"));
  EXPECT_THAT(refused.err, HasSubstr("convert --repair"));
  const CliRun r = freeform_cli("convert --repair " + q(dir / "bowtie.obj") + " " + q(dir / "fixed.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const ReadResult fixed = read_mesh((dir / "fixed.obj").string());
  EXPECT_NO_THROW(Mesh::from_soup(fixed.soup));
  ASSERT_EQ(fixed.attributes.uv.index.size(), 6u);
  EXPECT_EQ(fixed.attributes.uv.values[2 * static_cast<std::size_t>(fixed.attributes.uv.index[3])],
            0.2);  // vertex 3's second corner
}
