// End-to-end tests of `freeform deform`: outputs, report, exit codes, no partial files.
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "cli/cli_runner.h"
#include "param/param_fixtures.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>

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

// Issue 43: the precompute's wall and CPU time, whole and per phase (adding up to the whole),
// the threads it may use, and FREEFORM_THREADS capping them (the pool's and OpenBLAS's).
TEST(CliDeform, ReportsWallAndCpuTimePerPrecomputePhase) {
  const Workspace s;
  for (const char* threads : {"", "1"}) {
    SCOPED_TRACE(std::string("FREEFORM_THREADS=") + threads);
    if (*threads) setenv("FREEFORM_THREADS", threads, 1);
    const auto report = s.dir / "report.json";
    const auto start = std::chrono::steady_clock::now();
    const CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(s.edit(kGoodEdit)) + " -o " +
                                  q(s.dir / "out.ply") + " --report " + q(report));
    const double process_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    unsetenv("FREEFORM_THREADS");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(slurp(report))["precompute"];
    // model_setup is the rest of the whole: negative if a phase were counted twice.
    std::vector<std::string> names;
    for (const auto& p : j["phases"]) {
      names.push_back(p["name"]);
      EXPECT_GE(p["wall_ms"].get<double>(), 0.0) << names.back();
      EXPECT_GE(p["cpu_ms"].get<double>(), 0.0) << names.back();
    }
    EXPECT_EQ(names, (std::vector<std::string>{"operator_shape", "assembly", "factorization", "basis", "refinement",
                                               "model_setup"}));
    // Within the process's own run, measured here from outside.
    EXPECT_GT(j["wall_ms"].get<double>(), 0.0);
    EXPECT_LT(j["wall_ms"].get<double>(), process_ms);
    EXPECT_EQ(j["analysis_ahead"]["wall_ms"], 0.0);  // below BcmAnalysis::kMinFree
    EXPECT_FALSE(j["ordering"].get<std::string>().empty());
    EXPECT_GT(j["factor_nonzeros"].get<double>(), 0.0);
    if (*threads) {
      EXPECT_EQ(j["threads"], 1);
      EXPECT_LE(j["blas_threads"].get<int>(), 1);  // 0: not OpenBLAS
    } else {
      EXPECT_GE(j["threads"].get<int>(), 1);
    }
  }
}

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
  // Multiresolution is the default: decomposition, reconstruction time, fallback and problem counts.
  ASSERT_TRUE(j["multiresolution"].is_object());
  for (const char* key : {"decomposition_ms", "reconstruct_ms", "max_height"}) {
    ASSERT_TRUE(j["multiresolution"][key].is_number()) << key;
    EXPECT_GE(j["multiresolution"][key].get<double>(), 0.0) << key;
  }
  EXPECT_EQ(j["multiresolution"]["reconstruct_repeats"], 51);
  // The linear model's default encoding: every free vertex in the frame of its own base vertex.
  EXPECT_EQ(j["multiresolution"]["detail"], "vertex_frames");
  EXPECT_EQ(j["multiresolution"]["vertex_frames"].get<int>(), j["counts"]["free"].get<int>());
  EXPECT_EQ(j["multiresolution"]["normal_encoded"].get<int>() + j["multiresolution"]["fallback"].get<int>(), 0);
  EXPECT_EQ(j["multiresolution"]["flipped_triangles"], 0);
  EXPECT_EQ(j["multiresolution"]["overlaps"], 0);
  EXPECT_THAT(r.out, HasSubstr("multiresolution: decomposition"));
  EXPECT_EQ(count_files(s.dir.path()), 4u);  // mesh, edit, output, report: no temporaries
}

// "multiresolution": false gives plain BCM (the support is the fair surface: bumps flattened)
// and a null "multiresolution" entry; the default keeps the bumps.
TEST(CliDeform, MultiresolutionKeepsDetailAndCanBeTurnedOff) {
  const Workspace s;
  write_mesh((s.dir / "bumpy.off").string(), make_bumpy_plane(30, 30, 0.02, 3));
  const std::string edit = R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.35}},
      "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.08}}, "transform": {"translate": [0, 0, 0.1]}}])";
  const auto run = [&](const std::string& extra, const std::string& name) {
    const CliRun r = freeform_cli("deform " + q(s.dir / "bumpy.off") + " --edit " + q(s.edit(edit + extra + "}", name + ".json")) +
                                  " -o " + q(s.dir / (name + ".off")) + " --report " + q(s.dir / (name + ".report.json")));
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return nlohmann::json::parse(slurp(s.dir / (name + ".report.json")));
  };
  const auto jm = run("", "multires"), jp = run(R"(, "multiresolution": false)", "plain");
  EXPECT_TRUE(jm["multiresolution"].is_object());
  EXPECT_TRUE(jp["multiresolution"].is_null());
  const ReadResult in = read_mesh((s.dir / "bumpy.off").string()), m = read_mesh((s.dir / "multires.off").string()),
                   p = read_mesh((s.dir / "plain.off").string());
  // Plain BCM smooths the bumps in the support away, multires keeps them (amplitude 0.02).
  double max_diff = 0;
  for (std::size_t v = 0; v < in.soup.positions.size(); ++v)
    max_diff = std::max(max_diff, std::abs(m.soup.positions[v].z() - p.soup.positions[v].z()));
  EXPECT_GT(max_diff, 0.01);
  EXPECT_EQ(m.soup.positions[0], in.soup.positions[0]);  // fixed corner
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

// --deformation nonlinear (also with --sel/--def) runs the nonlinear model and reports its
// iterations; the iteration cap is reported on stderr; a bad model name is a usage error.
TEST(CliDeform, NonlinearModelFromTheCommandLine) {
  const Workspace s;
  const auto report = s.dir / "report.json";
  const auto edit = s.edit(kGoodEdit);
  CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " --deformation nonlinear -o " +
                          q(s.dir / "out.off") + " --report " + q(report));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("nonlinear: "));
  const auto j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j["deformation"], "nonlinear");
  EXPECT_TRUE(j["nonlinear"]["converged"].get<bool>());
  EXPECT_GE(j["nonlinear"]["iterations"].get<int>(), 1);
  EXPECT_EQ(j["evaluate_repeats"], 1);

  std::string capped = kGoodEdit;
  capped.replace(capped.find("\"order\": 2"), 10, R"("order": 2, "nonlinear": {"max_iterations": 1, "tolerance": 1e-12})");
  r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(s.edit(capped, "capped.json")) +
                   " --deformation nonlinear -o " + q(s.dir / "capped.off"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("stopped at its cap of 1 iterations"));

  std::string sel;
  for (int i = 0; i < 441; ++i) {
    const int x = i % 21, y = i / 21;
    sel += (x == 10 && y == 10) ? "2\n" : (x > 4 && x < 16 && y > 4 && y < 16) ? "1\n" : "0\n";
  }
  write_text(s.dir / "g.sel", sel);
  write_text(s.dir / "g.def", "1 0 0 0\n0 1 0 0\n0 0 1 0.3\n0 0 0 1\n");
  r = freeform_cli("deform " + q(s.mesh) + " --sel " + q(s.dir / "g.sel") + " --def " + q(s.dir / "g.def") +
                   " --deformation nonlinear -o " + q(s.dir / "sel.off"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(read_mesh((s.dir / "sel.off").string()).soup.positions[10 * 21 + 10].z(), 0.3, 1e-12);

  r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " --deformation rigid -o " + q(s.dir / "x.off"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(s.dir / "x.off"));
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
  // The report cannot be written: the mesh is not written either (all or nothing).
  r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(s.dir / "out.off") + " --report " +
                   q(s.dir / "no-such-dir" / "r.json"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_FALSE(std::filesystem::exists(s.dir / "out.off"));
  EXPECT_EQ(count_files(s.dir.path()), 2u);
  // An output from an earlier run survives a failed report (both are renamed only together).
  const auto earlier = s.dir / "earlier.off";
  { std::ofstream(earlier) << "earlier result"; }
  r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(earlier) + " --report " +
                   q(s.dir / "no-such-dir" / "r.json"));
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_EQ(slurp(earlier), "earlier result");
  EXPECT_EQ(count_files(s.dir.path()), 3u);
}

// The report or the output naming a file the edit was read from is refused before any work.
TEST(CliDeform, NeverOverwritesTheEditSelOrDefFiles) {
  const Workspace s;
  const auto edit = s.edit(kGoodEdit);
  const std::string edit_before = slurp(edit), mesh_before = slurp(s.mesh);
  for (const std::string& target : {edit.string(), s.mesh.string()}) {
    const CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(s.dir / "out.off") +
                                  " --report " + q(target));
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_THAT(r.err, HasSubstr("would overwrite"));
  }
  CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(edit) + " -o " + q(edit));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr("is the edit file"));
  EXPECT_EQ(slurp(edit), edit_before);
  EXPECT_EQ(slurp(s.mesh), mesh_before);
  EXPECT_FALSE(std::filesystem::exists(s.dir / "out.off"));
  // .sel / .def (the data folder's example pair), also through a symbolic link.
  const std::string sel = freeform::test::data_dir().string() + "/edits/plane.sel";
  const std::string def = freeform::test::data_dir().string() + "/edits/plane.def";
  const std::string plane = freeform::test::data_dir().string() + "/edits/plane-10x10.off";
  std::filesystem::create_symlink(sel, s.dir / "sel-link");
  r = freeform_cli("deform " + q(plane) + " --sel " + q(sel) + " --def " + q(def) + " -o " + q(s.dir / "o.off") +
                   " --report " + q(s.dir / "sel-link"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr(".sel file"));
  r = freeform_cli("deform " + q(plane) + " --sel " + q(sel) + " --def " + q(def) + " -o " + q(def));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_THAT(r.err, HasSubstr(".def file"));
  // Special files stream: the report to /dev/null, and /dev/null stays a device.
  r = freeform_cli("deform " + q(plane) + " --sel " + q(sel) + " --def " + q(def) + " -o " + q(s.dir / "o.off") +
                   " --report /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
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

// "anisotropic": true: the report says whether the operator was used, the principal extents
// and why it fell back (on stderr too: never silently).
TEST(CliDeform, AnisotropicReportAndFallback) {
  const Workspace s;
  std::string edit = kGoodEdit;
  edit.insert(edit.find('{') + 1, R"("anisotropic": true,)");
  const auto report = s.dir / "report.json";
  CliRun r = freeform_cli("deform " + q(s.mesh) + " --edit " + q(s.edit(edit)) + " -o " + q(s.dir / "out.off") +
                          " --report " + q(report));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr("anisotropic bending: principal extents"));
  auto j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j["anisotropic"]["requested"], true);
  EXPECT_EQ(j["anisotropic"]["used"], true);
  EXPECT_TRUE(j["anisotropic"]["fallback"].is_null());
  ASSERT_EQ(j["anisotropic"]["principal_extents"].size(), 2u);
  EXPECT_GT(j["anisotropic"]["principal_extents"][0].get<double>(), 0.5);
  EXPECT_GE(j["anisotropic"]["parametrization_ms"].get<double>(), 0.0);

  // A torus whose support contains its handle: genus 1, isotropic operator, reason reported.
  const auto torus = s.dir / "torus.off";
  write_mesh(torus.string(), test::torus(16, 8));
  std::string support;
  for (int i = 10; i < 128; ++i) support += (i > 10 ? "," : "") + std::to_string(i);
  r = freeform_cli("deform " + q(torus) + " --edit " +
                   q(s.edit(R"({"anisotropic": true, "support": {"vertices": [)" + support +
                                R"(]}, "handles": [{"region": {"vertices": [70]}, "transform": {"translate": [0, 0, 0.1]}}]})",
                            "torus.json")) +
                   " -o " + q(s.dir / "torus_out.off") + " --report " + q(report));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("anisotropic bending fell back to the isotropic operator"));
  EXPECT_THAT(r.err, HasSubstr("genus 1"));
  j = nlohmann::json::parse(slurp(report));
  EXPECT_EQ(j["anisotropic"]["requested"], true);
  EXPECT_EQ(j["anisotropic"]["used"], false);
  EXPECT_THAT(j["anisotropic"]["fallback"].get<std::string>(), HasSubstr("genus 1"));
}

// A textured quad grid (as kGoodEdit's grid, 400 quads) with normals, groups and a material:
// `deform` writes it back with only `v` and `vn` lines changed; another format says what it drops.
TEST(CliDeform, KeepsEverythingTheFileHeld) {
  const Workspace s;
  std::string obj = "# textured grid\nmtllib grid.mtl\no grid\n";
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) obj += fmt::format("v {} {} 0\n", i / 20.0, j / 20.0);
  for (int j = 0; j <= 20; ++j)
    for (int i = 0; i <= 20; ++i) obj += fmt::format("vt {} {}\n", i / 20.0, j / 20.0);
  for (int k = 0; k < 441; ++k) obj += "vn 0 0 1\n";
  for (int j = 0; j < 20; ++j) {
    obj += fmt::format("g row{}\nusemtl {}\ns 1\n", j, j % 2 ? "dark" : "light");
    for (int i = 0; i < 20; ++i) {
      const int a = j * 21 + i + 1, b = a + 1, c = a + 22, d = a + 21;
      obj += fmt::format("f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2} {3}/{3}/{3}\n", a, b, c, d);
    }
  }
  const auto in = s.dir / "grid.obj", out = s.dir / "out.obj";
  write_text(in, obj);
  // A gentle lift (slopes below 20 degrees), so a vertex's normal is close to each of its quads'.
  const std::string lift = R"({"support": {"geodesic": {"center": [0.5, 0.5, 0], "radius": 0.45}},
    "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.11}}, "transform": {"translate": [0, 0, 0.06]}}]})";
  CliRun r = freeform_cli("deform " + q(in) + " --edit " + q(s.edit(lift, "lift.json")) + " -o " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, ::testing::Not(HasSubstr("note:")));
  const std::string written = slurp(out);
  std::istringstream a(obj), b(written);
  int v_changed = 0, vn_changed = 0;
  for (std::string la, lb; std::getline(a, la);) {
    ASSERT_TRUE(std::getline(b, lb));
    if (la.rfind("v ", 0) == 0)
      v_changed += la != lb;
    else if (la.rfind("vn ", 0) == 0)
      vn_changed += la != lb;
    else
      ASSERT_EQ(la, lb);
  }
  EXPECT_GT(v_changed, 20);
  EXPECT_LT(v_changed, 441);  // the fixed part keeps its text
  EXPECT_GT(vn_changed, 20);  // the bent part's normals are recomputed...
  EXPECT_LT(vn_changed, 441);  // ...the rest keep theirs as written
  const ReadResult back = read_mesh(out.string());
  EXPECT_EQ(back.attributes.polygons.size(), 400);
  EXPECT_EQ(back.attributes.uv.rows(), 441);
  // Every corner's normal is unit and within a few degrees of its deformed quad's normal.
  double worst = 0;
  const Polygons& polygons = back.attributes.polygons;
  for (int p = 0; p < polygons.size(); ++p) {
    const int* c = &polygons.corners[static_cast<std::size_t>(polygons.offsets[static_cast<std::size_t>(p)])];
    const auto x = [&](int i) { return back.soup.positions[static_cast<std::size_t>(c[i])]; };
    const Vec3 face = (x(2) - x(0)).cross(x(3) - x(1)).normalized();
    for (int i = 0; i < 4; ++i) {
      const int row = back.attributes.normal.index[static_cast<std::size_t>(polygons.offsets[static_cast<std::size_t>(p)] + i)];
      const Vec3 n(&back.attributes.normal.values[static_cast<std::size_t>(row) * 3]);
      EXPECT_NEAR(n.norm(), 1.0, 1e-12);
      worst = std::max(worst, std::acos(std::clamp(n.dot(face), -1.0, 1.0)) * 180 / M_PI);
    }
  }
  EXPECT_LT(worst, 8.0);
  EXPECT_GT(worst, 0.5);  // the grid did bend

  // STL cannot hold polygons or texture coordinates: said on stderr, still written.
  r = freeform_cli("deform " + q(in) + " --edit " + q(s.edit(kGoodEdit)) + " -o " + q(s.dir / "out.stl"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("cannot hold the input's polygons"));
  EXPECT_THAT(r.err, HasSubstr("texture coordinates"));
  EXPECT_THAT(r.err, HasSubstr("groups"));
}
