// Sessions: save then load into a fresh Document gives the identical state and display,
// including applied edits (replayed with deform) and imported matrices; the mesh is found
// relative to the session after moving both; malformed files name the offending key.
#include "editor/document.h"
#include "editor_test_util.h"
#include "editor/session.h"

#include "freeform/common/error.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

namespace freeform::editor {
namespace {

namespace fs = std::filesystem;

using test_util::disc;

bool bitwise_equal(const VertexData<Vec3>& a, const VertexData<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.raw().data(), b.raw().data(), a.size() * sizeof(Vec3)) == 0;
}

void move_handle(Document& doc, int id, const Vec3& t, double degrees) {
  const Manipulator start = doc.state().find_handle(id)->manipulator;
  Manipulator m = start;
  m.translation = t;
  m.rotation = Manipulator::axis_angle(Vec3(0, 1, 0), degrees);
  doc.commit_manipulator(id, start, m);
}

// An edited document on dir/mesh/in.obj: one applied edit, then a current edit with an
// imported matrix handle moved further, an immovable handle and changed parameters.
void build(Document& doc, const test::ScratchDir& dir) {
  fs::create_directory(dir / "mesh");
  const std::string in = (dir / "mesh" / "in.obj").string();
  write_mesh(in, make_bumpy_plane(16, 16, 0.05, 2.0));
  doc.open(in);
  const Mesh& m = doc.rest_mesh();
  doc.set_region(PaintMode::Support, disc(m, Vec3(0.4, 0.5, 0), 0.3), false);
  doc.set_region(PaintMode::Handle, disc(m, Vec3(0.4, 0.5, 0), 0.08), false);
  doc.wait_for_precompute();
  move_handle(doc, doc.active_handle(), Vec3(0, 0, 0.15), 10);
  doc.wait_for_precompute();
  doc.apply();
  const std::string edit = (dir / "edit.json").string();
  write_file_atomic(edit, R"({"order": 2, "support": {"sphere": {"center": [0.6, 0.5, 0], "radius": 0.3}},
    "handles": [{"region": {"sphere": {"center": [0.6, 0.5, 0], "radius": 0.08}},
                 "transform": {"matrix": [[1, 0.1, 0, 0.02], [0, 1, 0, 0], [0, 0, 1, 0.1], [0, 0, 0, 1]]}},
                {"region": {"sphere": {"center": [0.85, 0.5, 0], "radius": 0.05}}, "fixed": true}],
    "smoothness": {"outer": 0.5}})");
  doc.import_edit(edit);
  move_handle(doc, doc.active_handle(), Vec3(0.02, 0, 0.05), -15);
  EditParameters p = doc.parameters();
  p.settings.smoothness.inner = 0.75;
  // Saved even while the linear model is chosen, with the model's other options.
  p.nonlinear.preserve_volume = false;
  p.nonlinear.max_iterations = 250;
  p.nonlinear.tolerance = 3e-5;
  p.allow_unanchored = true;
  doc.set_parameters(p);
  doc.wait_for_precompute();
}

TEST(Session, RoundTripIsExact) {
  test::ScratchDir dir;
  Document a;
  build(a, dir);
  ASSERT_TRUE(a.solver_current());
  ASSERT_TRUE(a.state().handles()[0].matrix.has_value());
  const std::string path = (dir / "work.session.json").string();
  a.save_session(path);
  EXPECT_FALSE(a.dirty());

  Document b;
  b.load_session(path);
  EXPECT_FALSE(b.dirty());
  EXPECT_TRUE(fs::equivalent(b.path(), a.path()));
  EXPECT_EQ(b.applied_edits().size(), 1u);
  EXPECT_TRUE(bitwise_equal(b.rest_mesh().positions(), a.rest_mesh().positions()));  // replayed Apply
  EXPECT_TRUE(b.state() == a.state());
  EXPECT_EQ(b.active_handle(), a.active_handle());
  EXPECT_FALSE(b.can_undo());
  b.wait_for_precompute();
  ASSERT_TRUE(b.solver_current()) << b.last_error();
  EXPECT_TRUE(bitwise_equal(b.display_positions(), a.display_positions()));
  // New handles never reuse the loaded ids.
  EXPECT_GT(b.new_handle(true), a.state().handles().back().id);
}

TEST(Session, MeshIsFoundRelativeToTheMovedSession) {
  test::ScratchDir dir;
  Document a;
  build(a, dir);
  fs::create_directory(dir / "a");
  a.save_session((dir / "a" / "s.json").string());
  const fs::path moved = dir / "moved";
  fs::create_directory(moved);
  fs::rename(dir / "a", moved / "a");
  fs::rename(dir / "mesh", moved / "mesh");
  Document b;
  b.load_session((moved / "a" / "s.json").string());
  EXPECT_TRUE(fs::equivalent(b.path(), moved / "mesh" / "in.obj"));
  EXPECT_TRUE(b.state() == a.state());
  fs::remove(moved / "mesh" / "in.obj");
  EXPECT_THROW(b.load_session((moved / "a" / "s.json").string()), IoError);
  EXPECT_TRUE(b.state() == a.state());  // unchanged after the error
}

std::string error_of(const std::string& text) {
  try {
    (void)parse_session_text(text, "s.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Session, MalformedFilesNameTheKey) {
  Session s;
  s.mesh_path = "/tmp/x.obj";
  s.n_vertices = 10;
  s.current = EditState(10);
  s.current.insert_handle(0, HandleState{3, true, {}, {}});
  s.current.set_vertex(Vertex(4), true, 3);
  s.current.set_vertex(Vertex(5), true, -1);
  const nlohmann::json good = nlohmann::json::parse(session_text(s));
  EXPECT_EQ(error_of(good.dump()), "no error");
  const Session back = parse_session_text(good.dump(), "s.json");
  EXPECT_TRUE(back.current == s.current);

  const auto with = [&](const std::function<void(nlohmann::json&)>& f) {
    nlohmann::json j = good;
    f(j);
    return error_of(j.dump());
  };
  const auto has = [](const std::string& msg, const std::string& part) {
    return msg.find(part) != std::string::npos ? ::testing::AssertionSuccess() : ::testing::AssertionFailure() << msg;
  };
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["handles"][0]["manipulatr"] = 1; }),
                  "s.json: unknown key \"current.handles[0].manipulatr\""));
  // The parameters are read by the library, with the edit file's keys and messages.
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["parameters"]["order"] = "3"; }),
                  "s.json: current.parameters: \"order\" must be an integer, got a string"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["parameters"]["smoothness"]["outer"] = 2.5; }),
                  "current.parameters: \"smoothness.outer\" must be in [0, 2]"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["parameters"]["deformation"] = "rigid"; }),
                  "current.parameters: \"deformation\" must be one of \"linear\", \"nonlinear\", got \"rigid\""));
  EXPECT_TRUE(has(with([](auto& j) { j.erase("mesh"); }), "missing required key \"mesh\""));
  EXPECT_TRUE(has(with([](auto& j) { j["version"] = 3; }), "unsupported session \"version\" 3"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["support"].push_back(10); }), "\"current.support[2]\" is vertex 10, outside"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["handles"][0]["manipulator"]["rotation"] = {1, 0, 0}; }),
                  "\"current.handles[0].manipulator.rotation\" must be a quaternion"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["handles"][0]["manipulator"]["scale"] = {1, 0, 1}; }),
                  "\"current.handles[0].manipulator\": manipulator scale has a zero component"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["handles"].push_back(j["current"]["handles"][0]); }),
                  "\"current.handles[1].id\" repeats the handle id 3"));
  EXPECT_TRUE(has(with([](auto& j) {
                    auto h = j["current"]["handles"][0];
                    h["id"] = 4;
                    j["current"]["handles"].push_back(h);
                  }),
                  "\"current.handles[1].vertices[0]\": vertex 4 is already in handle 3"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["active_handle"] = 9; }), "\"current.active_handle\" must be -1 or the id"));
  EXPECT_TRUE(has(with([](auto& j) { j["applied"] = {1}; }), "\"applied[0]\" must be an object"));
  EXPECT_TRUE(has(with([](auto& j) { j["current"]["handles"][0]["matrix"] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 0, 0}, {0, 0, 0, 1}}; }),
                  "\"current.handles[0].matrix\": transform matrix is singular"));
  EXPECT_TRUE(has(error_of("{\"version\": 1,\n \"mesh\": }"), "s.json:2: malformed JSON at column"));
  EXPECT_TRUE(has(error_of(R"({"version": 1, "version": 1})"), "the key \"version\" appears twice"));
}

TEST(Session, BadAppliedEditOrChangedMeshLeaveTheDocumentAlone) {
  test::ScratchDir dir;
  Document a;
  build(a, dir);
  const std::string path = (dir / "s.json").string();
  a.save_session(path);
  nlohmann::json j = nlohmann::json::parse(read_file(path));
  j["applied"][0]["handles"][0]["transfrom"] = 1;
  write_file_atomic(path, j.dump());
  Document b;
  b.open_mesh(Mesh::from_soup(make_plane(3, 3)));
  try {
    b.load_session(path);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("applied[0]: unknown key \"handles[0].transfrom\""), std::string::npos) << e.what();
  }
  EXPECT_EQ(b.rest_mesh().n_vertices(), 16);  // still the plane

  j = nlohmann::json::parse(read_file(path));
  j["applied"][0]["handles"][0].erase("transfrom");
  write_file_atomic(path, j.dump());
  write_mesh((dir / "mesh" / "in.obj").string(), make_plane(3, 3));  // someone replaced the mesh
  try {
    b.load_session(path);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("the mesh file changed"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace freeform::editor
