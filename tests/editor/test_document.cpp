// Document: the display equals the one-shot deform() of the state's edit (independent path),
// exported edits replay it, import restores the state, painting rules, Apply and its undo,
// the old solver staying in use, background failures and file errors.
#include "editor/document.h"
#include "editor_test_util.h"

#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "test_support.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <optional>
#include <span>
#include <sstream>
#include <thread>

namespace freeform::editor {
namespace {

using test_util::disc;

double max_diff(const VertexData<Vec3>& a, const VertexData<Vec3>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a.raw()[i] - b.raw()[i]).cwiseAbs().maxCoeff());
  return d;
}

bool bitwise_equal(const VertexData<Vec3>& a, const VertexData<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.raw().data(), b.raw().data(), a.size() * sizeof(Vec3)) == 0;
}

Manipulator moved(const Vec3& pivot) {
  Manipulator m;
  m.translation = Vec3(0.05, 0.0, 0.2);
  m.rotation = Manipulator::axis_angle(Vec3(1, 1, 0), 30);
  m.scale = Vec3(1.2, 1.0, 0.8);
  m.pivot = pivot;
  return m;
}

// Support disc, a movable handle in its middle, an immovable one beside it; the handle moved.
int setup(Document& doc, bool multires = true, bool nonlinear = false) {
  doc.open_mesh(Mesh::from_soup(make_bumpy_plane(20, 20, 0.05, 2.0)), "");
  const Mesh& m = doc.rest_mesh();
  EditParameters p;
  p.multiresolution = multires;
  p.deformation = nonlinear ? Deformation::Nonlinear : Deformation::Linear;
  doc.set_parameters(p);
  doc.set_region(PaintMode::Support, disc(m, Vec3(0.5, 0.5, 0), 0.4), false);
  doc.set_region(PaintMode::Handle, disc(m, Vec3(0.5, 0.5, 0), 0.1), false);
  const int id = doc.active_handle();
  doc.set_region(PaintMode::Immovable, disc(m, Vec3(0.75, 0.5, 0), 0.06), false);
  doc.wait_for_precompute();
  const Manipulator start = doc.state().find_handle(id)->manipulator;
  doc.commit_manipulator(id, start, moved(doc.handle_pivot(id)));
  doc.update_display();
  return id;
}

TEST(Document, DisplayEqualsDeformOfTheEdit) {
  for (const bool multires : {true, false}) {
    Document doc;
    setup(doc, multires);
    ASSERT_TRUE(doc.solver_current());
    EXPECT_EQ(doc.last_timings().reconstruction_ms > 0.0, multires);
    const Mesh expected = deform(doc.rest_mesh(), doc.state().to_edit(doc.rest_mesh()));
    EXPECT_LE(max_diff(doc.display_positions(), expected.positions()), 1e-12);
    EXPECT_GT(max_diff(doc.display_positions(), doc.rest_mesh().positions()), 0.05);  // it moved
  }
}

// The nonlinear model in the editor: it iterates on a worker thread while the display updates
// show its newest iterate; refining() stays true until it converged. The converged display is
// the model's solution: as close to the fixed point (solved to 1e-9) as the cold deform() of
// the edit is, which is a small fraction of how far linear BCM is from it.
TEST(Document, NonlinearDisplayRefinesToTheModelsSolution) {
  for (const bool multires : {true, false}) {
    Document doc;
    setup(doc, multires, true);
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (doc.refining() && std::chrono::steady_clock::now() < give_up) {
      doc.update_display();
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_FALSE(doc.refining());
    EXPECT_TRUE(doc.last_timings().converged);
    EXPECT_GT(doc.last_timings().iterations, 0);
    EXPECT_FALSE(doc.update_display().evaluated);  // converged: nothing more to compute
    Edit edit = doc.state().to_edit(doc.rest_mesh());
    ASSERT_EQ(edit.deformation, Deformation::Nonlinear);
    const Mesh cold = deform(doc.rest_mesh(), edit);
    edit.nonlinear.tolerance = 1e-9;
    edit.nonlinear.max_iterations = 100000;
    const Mesh fixed_point = deform(doc.rest_mesh(), edit);
    edit.deformation = Deformation::Linear;
    const Mesh linear = deform(doc.rest_mesh(), edit);
    const double gap = max_diff(linear.positions(), fixed_point.positions());
    EXPECT_GT(gap, 0.005) << "multires " << multires;  // the models differ (1.2 % of the support)
    EXPECT_LE(max_diff(doc.display_positions(), fixed_point.positions()), 0.1 * gap) << "multires " << multires;
    EXPECT_LE(max_diff(cold.positions(), fixed_point.positions()), 0.1 * gap) << "multires " << multires;
  }
}

// Between display resets a frame changes only display_touched(): the editor's O(support)
// display update relies on it. A new solver (new regions) resets the whole display.
TEST(Document, FramesChangeOnlyTheTouchedVerticesUntilAReset) {
  Document doc;
  const int id = setup(doc);
  const std::uint64_t reset = doc.display_reset_version();
  const std::span<const Vertex> touched = doc.display_touched();
  ASSERT_FALSE(touched.empty());
  const VertexData<Vec3> before = doc.display_positions();
  Manipulator m = doc.state().find_handle(id)->manipulator;
  m.translation += Vec3(0.03, -0.02, 0.1);
  doc.preview_manipulator(id, m);
  doc.update_display();
  EXPECT_EQ(doc.display_reset_version(), reset);
  int changed = 0;
  for (Vertex v : doc.rest_mesh().vertices()) {
    if (doc.display_positions()[v] == before[v]) continue;
    ++changed;
    EXPECT_TRUE(std::binary_search(touched.begin(), touched.end(), v)) << "vertex " << v.idx();
  }
  EXPECT_GT(changed, 0);
  // The problems of the display are those of the whole mesh (one-shot fold count).
  const std::optional<EditProblems> p = doc.display_problems();
  ASSERT_TRUE(p.has_value());
  EXPECT_EQ(p->non_finite, 0);
  EXPECT_EQ(p->folded_edges, count_folded_edges(doc.rest_mesh(), doc.rest_mesh().positions(), doc.display_positions()));
  doc.set_region(PaintMode::Support, disc(doc.rest_mesh(), Vec3(0.5, 0.85, 0), 0.04), true);  // new regions
  doc.wait_for_precompute();
  EXPECT_GT(doc.display_reset_version(), reset);
}

// Every key of docs/edit-format.md that an edit can set survives Import edit -> Export edit, compared
// key by key with the file's own writer (until 2026-11-28 the editor dropped allow_unanchored and
// nonlinear.max_iterations / tolerance).
TEST(Document, ImportThenExportKeepsEveryKeyOfTheEditFile) {
  test::ScratchDir dir;
  Document doc;
  doc.open_mesh(Mesh::from_soup(make_bumpy_plane(20, 20, 0.05, 2.0)), "");
  const std::string in = (dir / "in.json").string(), out = (dir / "out.json").string();
  write_file_atomic(in, R"({"order": 3, "smoothness": {"outer": 1.5, "inner": 0.5}, "anisotropic": true,
    "multiresolution": false, "deformation": "nonlinear", "allow_unanchored": true,
    "nonlinear": {"max_iterations": 250, "tolerance": 3e-5, "preserve_volume": false},
    "support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.4}},
    "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.1}},
                 "transform": {"matrix": [[1, 0, 0, 0.02], [0, 1, 0, 0], [0, 0, 1, 0.1], [0, 0, 0, 1]]}},
                {"region": {"sphere": {"center": [0.75, 0.5, 0], "radius": 0.06}}, "fixed": true}]})");
  doc.import_edit(in);
  doc.export_edit(out);
  const Json expected = edit_to_json(read_edit_file(in, doc.rest_mesh()));
  const Json exported = edit_to_json(read_edit_file(out, doc.rest_mesh()));
  for (const auto& [key, value] : expected.items()) {
    ASSERT_TRUE(exported.contains(key)) << key;
    EXPECT_EQ(exported[key], value) << key;
  }
  EXPECT_EQ(exported.size(), expected.size());
}

TEST(Document, ExportedEditReplaysTheDisplayAndImportRestoresTheState) {
  test::ScratchDir dir;
  Document doc;
  const int id = setup(doc);
  const std::string path = (dir / "edit.json").string();
  doc.export_edit(path);
  const Mesh replay = deform(doc.rest_mesh(), read_edit_file(path, doc.rest_mesh()));
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : doc.rest_mesh().positions()) lo = std::min(lo, p.minCoeff()), hi = std::max(hi, p.maxCoeff());
  EXPECT_LE(max_diff(doc.display_positions(), replay.positions()), 1e-9 * (hi - lo));
  EXPECT_TRUE(bitwise_equal(doc.display_positions(), replay.positions()));

  const EditState before = doc.state();
  const VertexData<Vec3> shown = doc.display_positions();
  doc.clear_regions();
  EXPECT_EQ(doc.state().n_support(), 0);
  doc.import_edit(path);
  const EditState& s = doc.state();
  EXPECT_EQ(s.support_vertices(), before.support_vertices());
  EXPECT_EQ(s.parameters(), before.parameters());
  ASSERT_EQ(s.handles().size(), 2u);
  EXPECT_GT(s.handles()[0].id, 1);  // fresh ids
  EXPECT_EQ(doc.active_handle(), s.handles()[0].id);
  EXPECT_EQ(s.handle_vertices(s.handles()[0].id), before.handle_vertices(id));
  EXPECT_FALSE(s.handles()[1].movable);
  EXPECT_TRUE(s.transform(s.handles()[0].id, doc.rest_mesh()).matrix() == before.transform(id, doc.rest_mesh()).matrix());
  doc.wait_for_precompute();
  EXPECT_TRUE(bitwise_equal(doc.display_positions(), shown));
  doc.undo();  // back to the cleared state
  EXPECT_EQ(doc.state().n_support(), 0);
  EXPECT_THROW(doc.export_edit(path), InvalidInput);  // nothing to export
}

TEST(Document, PaintingRules) {
  Document doc;
  doc.open_mesh(Mesh::from_soup(make_plane(10, 10)));
  const Mesh& m = doc.rest_mesh();
  const auto hv = disc(m, Vec3(0.5, 0.5, 0), 0.15);
  const std::uint64_t colours = doc.region_version();
  doc.begin_stroke(PaintMode::Handle, false);  // no active handle: one is created
  doc.stroke(std::span(hv).first(3));
  EXPECT_NE(doc.region_version(), colours);  // live colours during the stroke
  doc.stroke(std::span(hv).subspan(3));
  doc.end_stroke();
  EXPECT_EQ(doc.history().undo_size(), 1u);  // one stroke, one step
  const int h = doc.active_handle();
  ASSERT_GE(h, 0);
  EXPECT_TRUE(doc.state().find_handle(h)->movable);
  EXPECT_EQ(doc.state().handle_size(h), static_cast<int>(hv.size()));
  EXPECT_EQ(doc.state().n_support(), static_cast<int>(hv.size()));  // handle vertices count as support
  Vec3 c = Vec3::Zero();
  for (Vertex v : hv) c += m.position(v);
  EXPECT_LT((doc.handle_pivot(h) - c / static_cast<double>(hv.size())).norm(), 1e-15);
  EXPECT_NE(doc.regions_problem().find("all handle"), std::string::npos);

  doc.set_region(PaintMode::Immovable, std::span(hv).first(2), false);  // steals two vertices
  const int im = doc.active_handle();
  EXPECT_NE(im, h);
  EXPECT_FALSE(doc.state().find_handle(im)->movable);
  EXPECT_EQ(doc.state().handle_size(h), static_cast<int>(hv.size()) - 2);
  doc.set_region(PaintMode::Handle, std::span(hv).first(1), true);  // erases movable only
  EXPECT_EQ(doc.state().handle_size(im), 2);
  doc.set_region(PaintMode::Immovable, std::span(hv).first(1), true);
  EXPECT_EQ(doc.state().handle_size(im), 1);
  EXPECT_FALSE(doc.state().in_support(hv[0]));  // its own flag was never set

  doc.set_active_handle(h);
  doc.set_region(PaintMode::Handle, hv, true);
  EXPECT_EQ(doc.state().handle_size(h), 0);
  EXPECT_NE(doc.regions_problem().find("has no vertices"), std::string::npos);
  EXPECT_THROW(doc.stroke(hv), InvalidInput);  // no stroke in progress
  const Vertex bad(100000);
  EXPECT_THROW(doc.set_region(PaintMode::Support, std::span(&bad, 1), false), InvalidInput);
  EXPECT_FALSE(doc.stroking());

  while (doc.can_undo()) doc.undo();
  EXPECT_TRUE(doc.state() == EditState(m.n_vertices()));
  EXPECT_EQ(doc.active_handle(), -1);  // the selected handle was undone
}

TEST(Document, ApplyBakesAndUndoRestoresExactly) {
  Document doc;
  const int id = setup(doc);
  const VertexData<Vec3> original = doc.rest_mesh().positions();
  const VertexData<Vec3> shown = doc.display_positions();
  const EditState regions = doc.state();
  EXPECT_EQ(doc.apply_blocker(), "");
  doc.apply();
  EXPECT_TRUE(bitwise_equal(doc.rest_mesh().positions(), shown));
  EXPECT_EQ(doc.applied_edits().size(), 1u);
  EXPECT_TRUE(is_identity(doc.state().find_handle(id)->manipulator));
  EXPECT_EQ(doc.state().support_vertices(), regions.support_vertices());
  EXPECT_EQ(doc.state().handle_vertices(id), regions.handle_vertices(id));
  Vec3 c = Vec3::Zero();
  for (Vertex v : regions.handle_vertices(id)) c += doc.rest_mesh().position(v);
  EXPECT_LT((*doc.state().find_handle(id)->manipulator.pivot - c / regions.handle_size(id)).norm(), 1e-15);
  doc.update_display();  // the new rest until the new solver is ready
  EXPECT_TRUE(bitwise_equal(doc.display_positions(), shown));
  doc.wait_for_precompute();
  EXPECT_LE(max_diff(doc.display_positions(), shown), 1e-12);  // identity reproduces (multires)

  doc.undo();
  EXPECT_TRUE(bitwise_equal(doc.rest_mesh().positions(), original));
  EXPECT_TRUE(doc.state() == regions);
  EXPECT_TRUE(doc.applied_edits().empty());
  doc.wait_for_precompute();
  EXPECT_TRUE(bitwise_equal(doc.display_positions(), shown));
  doc.redo();
  EXPECT_TRUE(bitwise_equal(doc.rest_mesh().positions(), shown));
  EXPECT_EQ(doc.applied_edits().size(), 1u);
}

TEST(Document, OldSolverStaysInUseWithTheHandlesItKnows) {
  Document doc;
  const int id = setup(doc);
  const Edit old_edit = doc.state().to_edit(doc.rest_mesh());
  doc.new_handle(true);  // empty: the regions are invalid, no new solver
  EXPECT_NE(doc.regions_problem().find("no vertices"), std::string::npos);
  EXPECT_FALSE(doc.solver_current());
  EXPECT_NE(doc.apply_blocker().find("no vertices"), std::string::npos);
  EXPECT_THROW(doc.apply(), InvalidInput);
  Manipulator m = moved(doc.handle_pivot(id));
  m.translation = Vec3(-0.1, 0.1, 0.3);
  doc.preview_manipulator(id, m);
  EXPECT_EQ(doc.history().undo_size(), 5u);  // preview records nothing
  const FrameTimings t = doc.update_display();
  EXPECT_TRUE(t.evaluated);
  Edit expected_edit = old_edit;
  expected_edit.handles[0].matrix = doc.state().transform(id, doc.rest_mesh());
  const Mesh expected = deform(doc.rest_mesh(), expected_edit);
  EXPECT_LE(max_diff(doc.display_positions(), expected.positions()), 1e-12);
  EXPECT_FALSE(doc.update_display().evaluated);  // nothing changed
}

TEST(Document, FailedPrecomputeReportsAndKeepsTheSolver) {
  Document doc;
  setup(doc);
  const auto solver = doc.solver();
  Edit old_edit = doc.state().to_edit(doc.rest_mesh());
  old_edit.handles[0].matrix = Eigen::Affine3d::Identity();
  doc.clear_regions();
  std::vector<Vertex> all;
  for (Vertex v : doc.rest_mesh().vertices()) all.push_back(v);
  doc.set_region(PaintMode::Support, all, false);  // nothing holds the surface
  doc.wait_for_precompute();
  EXPECT_NE(doc.last_error().find("undetermined"), std::string::npos) << doc.last_error();
  EXPECT_EQ(doc.solver(), solver);
  EXPECT_NE(doc.apply_blocker().find("failed"), std::string::npos);
  EXPECT_FALSE(doc.precompute_running());
  // The old solver stays; the handle it knows is gone, so it stays put.
  EXPECT_LE(max_diff(doc.display_positions(), deform(doc.rest_mesh(), old_edit).positions()), 1e-12);
}

TEST(Document, ParametersAndManipulatorSteps) {
  Document doc;
  const int id = setup(doc);
  const std::size_t steps = doc.history().undo_size();
  EditParameters p = doc.parameters();
  p.settings.order = 2;
  doc.set_parameters(p);
  EXPECT_EQ(doc.parameters().settings.smoothness.outer, 1.0);  // clamped
  doc.set_parameters(doc.parameters());     // unchanged: no step
  EXPECT_EQ(doc.history().undo_size(), steps + 1);
  const Manipulator now = doc.state().find_handle(id)->manipulator;
  doc.commit_manipulator(id, now, now);
  EXPECT_EQ(doc.history().undo_size(), steps + 1);
  EXPECT_THROW(doc.preview_manipulator(id + 1, now), InvalidInput);  // the immovable handle
  Manipulator bad = now;
  bad.scale = Vec3(1, 0, 1);
  EXPECT_THROW(doc.preview_manipulator(id, bad), InvalidInput);
  doc.undo();
  EXPECT_EQ(doc.parameters().settings.order, 3);
  EXPECT_EQ(doc.parameters().settings.smoothness.outer, 2.0);
  doc.undo();  // the manipulator of setup()
  EXPECT_TRUE(is_identity(doc.state().find_handle(id)->manipulator));
  doc.wait_for_precompute();
}

TEST(Document, FilesAndDirtyFlag) {
  test::ScratchDir dir;
  const std::string in = (dir / "in.obj").string();
  write_mesh(in, make_bumpy_plane(12, 12, 0.05, 2.0));
  Document doc;
  EXPECT_THROW(doc.open((dir / "missing.obj").string()), IoError);
  EXPECT_FALSE(doc.has_mesh());
  doc.open(in);
  EXPECT_FALSE(doc.dirty());
  EXPECT_THROW(doc.open((dir / "missing.obj").string()), IoError);
  EXPECT_EQ(doc.path(), in);  // unchanged
  // A non-manifold file is refused naming it and the repair that keeps its attributes.
  const std::string bowtie = (dir / "bowtie.obj").string();
  { std::ofstream(bowtie) << "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0 2 0\nv 1 2 0\nf 1 2 3\nf 3 5 4\n"; }
  try {
    doc.open(bowtie);
    ADD_FAILURE() << "a non-manifold file was opened";
  } catch (const TopologyError& e) {
    EXPECT_THAT(e.what(), ::testing::HasSubstr(bowtie + ": mesh is not manifold"));
    EXPECT_THAT(e.what(), ::testing::HasSubstr("convert --repair"));
  }
  EXPECT_EQ(doc.path(), in);
  const Mesh& m = doc.rest_mesh();
  doc.set_region(PaintMode::Support, disc(m, Vec3(0.5, 0.5, 0), 0.4), false);
  doc.set_region(PaintMode::Handle, disc(m, Vec3(0.5, 0.5, 0), 0.1), false);
  EXPECT_TRUE(doc.dirty());
  doc.wait_for_precompute();
  const int id = doc.active_handle();
  doc.commit_manipulator(id, doc.state().find_handle(id)->manipulator, moved(doc.handle_pivot(id)));
  EXPECT_THROW(doc.save_mesh(in), InvalidInput);
  const std::string out = (dir / "out.obj").string();
  doc.save_mesh(out);
  EXPECT_FALSE(doc.dirty());
  const ReadResult back = read_mesh(out);
  ASSERT_EQ(back.soup.positions.size(), static_cast<std::size_t>(m.n_vertices()));
  for (std::size_t i = 0; i < back.soup.positions.size(); ++i)
    EXPECT_EQ(back.soup.positions[i], doc.display_positions().raw()[i]);
  doc.save_mesh(in, true);  // allowed when asked
  EXPECT_THROW(doc.save_session((dir / "s.json").string()), InvalidInput);  // the original is gone
}

// Saving writes the opened file back with the display positions: its texture coordinates,
// groups and materials stay, also after a session round trip; another format says what it drops.
TEST(Document, SavingKeepsWhatTheFileHeld) {
  test::ScratchDir dir;
  const TriangleSoup plane = make_bumpy_plane(12, 12, 0.05, 2.0);
  std::string obj = "mtllib plane.mtl\ng plane\nusemtl clay\n";
  for (const Vec3& p : plane.positions) obj += fmt::format("v {} {} {}\nvt {} {}\n", p.x(), p.y(), p.z(), p.x(), p.y());
  for (const Tri& f : plane.faces) obj += fmt::format("f {0}/{0} {1}/{1} {2}/{2}\n", f[0] + 1, f[1] + 1, f[2] + 1);
  const std::string in = (dir / "in.obj").string();
  write_file_atomic(in, obj);
  Document doc;
  doc.open(in);
  const Mesh& m = doc.rest_mesh();
  doc.set_region(PaintMode::Support, disc(m, Vec3(0.5, 0.5, 0), 0.4), false);
  doc.set_region(PaintMode::Handle, disc(m, Vec3(0.5, 0.5, 0), 0.1), false);
  doc.wait_for_precompute();
  const int id = doc.active_handle();
  doc.commit_manipulator(id, doc.state().find_handle(id)->manipulator, moved(doc.handle_pivot(id)));
  const auto without_positions = [](const std::string& text) {
    std::string out;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("v ", 0) != 0) out += line + "\n";
    return out;
  };
  const std::string out = (dir / "out.obj").string();
  EXPECT_TRUE(doc.save_mesh(out).empty());
  EXPECT_EQ(without_positions(read_file(out)), without_positions(obj));
  EXPECT_NE(read_file(out), obj);
  const ReadResult back = read_mesh(out);
  for (std::size_t i = 0; i < back.soup.positions.size(); ++i)
    EXPECT_EQ(back.soup.positions[i], doc.display_positions().raw()[i]);
  EXPECT_THAT(doc.save_mesh((dir / "out.stl").string()), ::testing::Contains(::testing::HasSubstr("texture coordinates")));

  const std::string session = (dir / "s.json").string();
  doc.save_session(session);
  Document again;
  again.load_session(session);
  again.wait_for_precompute();
  const std::string out2 = (dir / "out2.obj").string();
  again.save_mesh(out2);
  EXPECT_EQ(without_positions(read_file(out2)), without_positions(obj));
}

}  // namespace
}  // namespace freeform::editor
