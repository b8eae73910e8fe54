// End-to-end tests of `freeform deform`: outputs, report, exit codes, no partial files.
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "cli/cli_runner.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

using namespace freeform;
using ::testing::HasSubstr;
using namespace freeform::test;

namespace {

std::size_t count_files(const std::filesystem::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

// A 21 x 21 grid on the unit square (441 vertices, 800 faces) as OFF, and a valid edit.
struct Workspace {
  test::ScratchDir dir;
  std::filesystem::path mesh = dir / "grid.off";
  Workspace() { write_mesh(mesh.string(), make_plane(20, 20)); }
  std::filesystem::path edit(const std::string& text, const std::string& name = "edit.json") const {
    write_text(dir / name, text);
    return dir / name;
  }
};

const char* kGoodEdit = R"({
  "order": 2,
  "support": {"geodesic": {"center": [0.5, 0.5, 0], "radius": 0.4}},
  "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.11}},
               "transform": {"translate": [0, 0, 0.2], "rotate": {"axis": [1, 0, 0], "degrees": 10}}},
              {"region": {"vertices": [0]}, "fixed": true}],
  "smoothness": {"inner": 0.5}
})";

}  // namespace

TEST(CliDeform, EditWritesMeshAndReport) {
  const Workspace s;
  const auto out = s.dir / "out.ply";
  const auto report = s.dir / "report.json";
  const CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(s.edit(kGoodEdit)) + " -o " + q(out) +
                             " --report " + q(report));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("wrote"));
  const ReadResult in = read_mesh(s.mesh.string()), back = read_mesh(out.string());
  ASSERT_EQ(back.soup.positions.size(), in.soup.positions.size());
  EXPECT_EQ(back.soup.faces, in.soup.faces);
  // The centre vertex (handle) moved up, a corner (fixed) did not.
  EXPECT_GT(back.soup.positions[10 * 21 + 10].z(), 0.15);
  EXPECT_EQ(back.soup.positions[440], in.soup.positions[440]);

  const auto j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j["order"], 2);
  EXPECT_EQ(j["smoothness"]["outer"], 1.0);
  EXPECT_EQ(j["smoothness"]["inner"], 0.5);
  ASSERT_TRUE(j["counts"]["free"].is_number_integer());
  ASSERT_TRUE(j["counts"]["fixed"].is_number_integer());
  ASSERT_EQ(j["counts"]["handles"].size(), 2u);
  EXPECT_EQ(j["counts"]["handles"][0]["movable"], true);
  EXPECT_EQ(j["counts"]["handles"][1]["movable"], false);
  EXPECT_EQ(j["counts"]["handles"][1]["vertices"], 1);
  const int handle0 = j["counts"]["handles"][0]["vertices"];
  EXPECT_EQ(handle0, 13);  // lattice points with x^2 + y^2 <= 2.2^2 spacings
  EXPECT_EQ(j["counts"]["free"].get<int>() + j["counts"]["fixed"].get<int>() + handle0 + 1, 441);
  EXPECT_TRUE(j["solver"].is_string());
  EXPECT_FALSE(j["solver"].get<std::string>().empty());
  EXPECT_TRUE(j["symmetric"].is_boolean());
  for (const char* key : {"assembly", "factorization", "basis", "evaluate"}) {
    ASSERT_TRUE(j["timings_ms"][key].is_number()) << key;
    EXPECT_GE(j["timings_ms"][key].get<double>(), 0.0) << key;
  }
  EXPECT_EQ(j["evaluate_repeats"], 51);
  ASSERT_TRUE(j["residual"].is_number());
  EXPECT_LT(j["residual"].get<double>(), 1e-6);
  ASSERT_TRUE(j["peak_memory_mb"].is_number());
  EXPECT_GT(j["peak_memory_mb"].get<double>(), 0.0);
  EXPECT_EQ(count_files(s.dir.path()), 4u);  // mesh, edit, output, report: no temporaries
}

TEST(CliDeform, SelDefPair) {
  const Workspace s;
  std::string sel = "# 0 fixed, 1 free, 2 handle\n";
  for (int i = 0; i < 441; ++i) {
    const int x = i % 21, y = i / 21;
    sel += (x == 10 && y == 10) ? "2\n" : (x > 4 && x < 16 && y > 4 && y < 16) ? "1\n" : "0\n";
  }
  write_text(s.dir / "g.sel", sel);
  write_text(s.dir / "g.def", "# up by 0.3\n1 0 0 0\n0 1 0 0\n0 0 1 0.3\n0 0 0 1\n");
  const auto out = s.dir / "out.obj";
  const CliRun r = freeform_cli("deform " + q(s.mesh) + " --sel " + q(s.dir / "g.sel") + " --def " + q(s.dir / "g.def") +
                             " --order 3 -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const ReadResult back = read_mesh(out.string());
  EXPECT_NEAR(back.soup.positions[10 * 21 + 10].z(), 0.3, 1e-12);
  EXPECT_EQ(back.soup.positions[0].z(), 0.0);

  write_text(s.dir / "short.sel", "# too short\n0\n1\n2\n");
  const CliRun bad = freeform_cli("deform " + q(s.mesh) + " --sel " + q(s.dir / "short.sel") + " --def " +
                               q(s.dir / "g.def") + " -o " + q(s.dir / "bad.obj"));
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_THAT(bad.err, HasSubstr("short.sel:4:"));
  EXPECT_FALSE(std::filesystem::exists(s.dir / "bad.obj"));
}

// Every bad edit: exit 1, a message that says what is wrong, and no output at all.
TEST(CliDeform, BadEditsExitOneAndWriteNothing) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"support": {"vertices": []}})", "support selects no vertex"},
      {R"({"support": {"sphere": {"center": [5, 5, 5], "radius": 0.1}}})", "support selects no vertex"},
      {R"({"support": {"vertices": [1, 2]}, "handles": [{"region": {"vertices": []}}]})",
       "handles[0].region selects no vertex"},
      {R"({"support": {"vertices": [1, 2]}, "handles": [{"region": {"vertices": [441]}}]})",
       "handles[0].region: vertex index 441"},
      {R"({"order": 5, "support": {"vertices": [1, 2]}})", "\"order\" must be 1"},
      {R"({"order": 2, "smoothness": {"outer": 3}, "support": {"vertices": [1, 2]}})", "\"smoothness.outer\" must be in [0, 1]"},
      {R"({"support": {"vertices": [22]}, "handles": [{"region": {"vertices": [23]}, "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,0,0],[0,0,0,1]]}}]})",
       "is singular"},
      {R"({"support": {"vertices": [22]}, "handles": [{"region": {"vertices": [23]}, "transform": {"translate": [1e999, 0, 0]}}]})",
       "number overflow"},
      {R"({"support": {"vertices": [22]}, "handles": [{"region": {"vertices": [23]}, "transform": {"scale": [0, 1, 1]}}]})",
       "zero scale"},
      {R"({"support": {"vertices": [22]}, "handles": [{"region": {"vertices": [23]}, "transfrom": {}}]})",
       "unknown key \"handles[0].transfrom\""},
      {R"({"support": {"vertices": [22]}, "anisotropic": true})", "not available yet"},
      {R"({"support": {"vertices": [22]}, "multiresolution": true})", "not available yet"},
      {"{\n  \"support\": {\"vertices\": [22]},\n  \"order\": 2,,\n}", "edit.json:3: malformed JSON at column"},
  };
  const Workspace s;
  for (const auto& [text, message] : cases) {
    const auto out = s.dir / "out.off";
    const CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(s.edit(text)) + " -o " + q(out) + " --report " +
                               q(s.dir / "r.json"));
    EXPECT_EQ(r.exit_code, 1) << text << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(message)) << text;
    EXPECT_THAT(r.err, HasSubstr("freeform: error:")) << text;
    EXPECT_FALSE(std::filesystem::exists(out)) << text;
    EXPECT_FALSE(std::filesystem::exists(s.dir / "r.json")) << text;
    EXPECT_EQ(count_files(s.dir.path()), 2u) << text;
  }
}

TEST(CliDeform, UnconstrainedFreeRegionIsRefused) {
  test::ScratchDir dir;
  write_mesh((dir / "sphere.off").string(), make_icosphere(1));  // closed, 42 vertices
  std::string all;
  for (int i = 0; i < 42; ++i) all += (i ? "," : "") + std::to_string(i);
  write_text(dir / "edit.json", R"({"support": {"vertices": [)" + all + "]}}");
  const CliRun r = freeform_cli("deform " + q(dir / "sphere.off") + " --edit " + q(dir / "edit.json") + " -o " +
                             q(dir / "out.off"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.off"));
}

TEST(CliDeform, OutputErrorsExitThreeAndLeaveNothing) {
  const Workspace s;
  const auto edit = s.edit(kGoodEdit);
  CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(s.dir / "no-such-dir" / "out.off"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_THAT(r.err, HasSubstr("no-such-dir"));
  // The report cannot be written: the mesh output is removed again (all or nothing).
  r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(s.dir / "out.off") + " --report " +
                   q(s.dir / "no-such-dir" / "r.json"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_FALSE(std::filesystem::exists(s.dir / "out.off"));
  EXPECT_EQ(count_files(s.dir.path()), 2u);
}

TEST(CliDeform, RefusesToOverwriteItsInput) {
  const Workspace s;
  const std::string before = slurp(s.mesh);
  const auto edit = s.edit(kGoodEdit);
  CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(s.mesh));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_THAT(r.err, HasSubstr("--overwrite-input"));
  EXPECT_EQ(slurp(s.mesh), before);
  r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(s.mesh) + " --overwrite-input");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(slurp(s.mesh), before);
}

TEST(CliDeform, UsageErrorsExitTwo) {
  const Workspace s;
  const auto edit = s.edit(kGoodEdit);
  EXPECT_EQ(freeform_cli("deform " + q(s.mesh) + " -o " + q(s.dir / "o.off")).exit_code, 2);
  EXPECT_EQ(freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit)).exit_code, 2);  // no -o
  EXPECT_EQ(freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " --sel a.sel --def a.def -o " + q(s.dir / "o.off")).exit_code, 2);
  EXPECT_EQ(freeform_cli("deform " + q(s.mesh) + " --sel a.sel -o " + q(s.dir / "o.off")).exit_code, 2);
  EXPECT_EQ(freeform_cli("deform " + q(s.mesh) + " --sel a.sel --def a.def --order 4 -o " + q(s.dir / "o.off")).exit_code, 2);
  const CliRun help = freeform_cli("deform --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_THAT(help.out, HasSubstr("Exit codes"));
  EXPECT_EQ(count_files(s.dir.path()), 2u);
}
