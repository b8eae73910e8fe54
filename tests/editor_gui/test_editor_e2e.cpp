// End to end, as a user would: freeform-editor on a virtual display (Xvfb), driven by xdotool.
// Load a mesh, paint a support and a handle with the brush, drag the gizmo's centre, export
// the edit and save the mesh through the panel; then `freeform deform` with the exported edit
// must reproduce the saved mesh (max vertex difference <= 1e-9 of the bounding-box diagonal).
//
// The mesh is a bumpy plane facing the default front view, so it fills the viewport's centre.
// The panel is reached through its keyboard shortcuts (docs/editor.md): 1 / 2 paint mode,
// Ctrl+E export edit, Ctrl+Shift+S save as. ImGui reads the pointer once per frame, so every
// press waits a moment after the pointer moved.
#include "x_session.h"

#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "test_support.h"

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <thread>

namespace freeform {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// Viewport centre: the panel ends at x = 351, the status bar starts at y = 757.
constexpr int kCx = 815, kCy = 378;

bool wait_for_file(const fs::path& p, std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (fs::exists(p) && fs::file_size(p) > 0) return true;
    std::this_thread::sleep_for(200ms);
  }
  return false;
}

// With FREEFORM_E2E_SHOTS=DIR set, screenshots of each step go there (needs ImageMagick).
void shot(const test::XSession& x, const std::string& name) {
  const char* dir = std::getenv("FREEFORM_E2E_SHOTS");
  if (dir && *dir) x.shell("import -window root '" + std::string(dir) + "/" + name + ".png'");
}

// What went wrong: the scratch folder's files and the editor's log.
std::string diagnose(const fs::path& dir) {
  std::string out = "files:";
  for (const auto& e : fs::directory_iterator(dir)) out += " " + e.path().filename().string();
  std::ifstream log(dir / "editor.log");
  out += "\neditor log:\n" + std::string(std::istreambuf_iterator<char>(log), {});
  return out;
}

std::string at(int x, int y) { return std::to_string(x) + " " + std::to_string(y); }

double bbox_diagonal(const TriangleSoup& s) {
  Vec3 lo = s.positions.front(), hi = lo;
  for (const Vec3& p : s.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).norm();
}

TEST(EditorEndToEnd, PaintDragExportSaveThenDeformReproduces) {
  test::ScratchDir dir;
  // A bumpy plane in the xz-plane, facing the front view (eye on -y).
  TriangleSoup soup = make_bumpy_plane(40, 40, 0.02, 3.0, 2.0, 2.0);
  for (Vec3& p : soup.positions) p = Vec3(p.x(), -p.z(), p.y());
  const fs::path input = dir.path() / "plane.off", edit = dir.path() / "edit.json", saved = dir.path() / "saved.off",
                 replay = dir.path() / "replay.off";
  write_mesh(input.string(), soup);

  test::XSession x(1280, 800);
  // One retry: a display that was just freed can refuse the first client (seen once on CI).
  bool started = x.start_editor(FREEFORM_EDITOR_PATH, {input.string(), "--size", "1280x800"}, dir.path());
  if (!started && !x.editor_running())
    started = x.start_editor(FREEFORM_EDITOR_PATH, {input.string(), "--size", "1280x800"}, dir.path());
  ASSERT_TRUE(started) << "the editor window did not appear on " << x.display() << " (exit code " << x.exit_code()
                       << "); " << diagnose(dir.path());
  std::this_thread::sleep_for(2s);

  // Support: three wide brush strokes across the middle (radius 40 px * 1.15^8 = 122 px).
  for (int i = 0; i < 8; ++i) ASSERT_TRUE(x.xdotool("key bracketright"));
  for (int dy : {-110, 0, 110}) {
    std::string stroke = "mousemove " + at(kCx - 220, kCy + dy) + " sleep 0.3 mousedown 1";
    for (int s = 1; s <= 8; ++s) stroke += " sleep 0.05 mousemove " + at(kCx - 220 + 55 * s, kCy + dy);
    ASSERT_TRUE(x.xdotool(stroke + " sleep 0.3 mouseup 1"));
    std::this_thread::sleep_for(300ms);
  }
  // Handle: one dab of the 40 px brush at the centre.
  ASSERT_TRUE(x.xdotool("key 2"));
  for (int i = 0; i < 8; ++i) ASSERT_TRUE(x.xdotool("key bracketleft"));
  ASSERT_TRUE(x.xdotool("mousemove " + at(kCx, kCy) + " sleep 0.3 click 1"));
  std::this_thread::sleep_for(6s);  // the background precompute (well under a second here)
  shot(x, "1-painted");

  // Drag the gizmo's free centre up by 70 pixels.
  ASSERT_TRUE(x.xdotool("mousemove " + at(kCx, kCy) + " sleep 0.3 mousedown 1 sleep 0.1 mousemove " + at(kCx, kCy - 20) +
                        " sleep 0.1 mousemove " + at(kCx, kCy - 50) + " sleep 0.1 mousemove " + at(kCx, kCy - 70) +
                        " sleep 0.3 mouseup 1"));
  std::this_thread::sleep_for(2s);
  shot(x, "2-dragged");

  // Export the edit and save the mesh through the panel's path prompts.
  // Each prompt opens a frame or two later: type only once it surely has the keyboard, or the
  // letters would reach the viewport as tool keys.
  ASSERT_TRUE(x.xdotool("key ctrl+e"));
  std::this_thread::sleep_for(2s);
  // The prompt's suggested path is selected: typing replaces it.
  ASSERT_TRUE(x.xdotool("type --delay 20 '" + edit.string() + "'"));
  std::this_thread::sleep_for(1500ms);
  shot(x, "3-export-prompt");
  ASSERT_TRUE(x.xdotool("key Return"));
  ASSERT_TRUE(wait_for_file(edit, 20s)) << "no exported edit; " << diagnose(dir.path());
  ASSERT_TRUE(x.xdotool("key ctrl+shift+s"));
  std::this_thread::sleep_for(2s);
  ASSERT_TRUE(x.xdotool("type --delay 20 '" + saved.string() + "'"));
  std::this_thread::sleep_for(1500ms);
  shot(x, "4-save-prompt");
  ASSERT_TRUE(x.xdotool("key Return"));
  ASSERT_TRUE(wait_for_file(saved, 20s)) << "no saved mesh; " << diagnose(dir.path());

  // Quit: the mesh was saved, so the editor closes without asking.
  ASSERT_TRUE(x.xdotool("key ctrl+q"));
  EXPECT_TRUE(x.wait_editor_exit(20s));
  EXPECT_EQ(x.exit_code(), 0);

  // The exported edit is a real one: a support, one movable handle, a non-identity matrix.
  std::ifstream in(edit);
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j.at("handles").size(), 1u);
  EXPECT_GT(j.at("support").at("vertices").size(), 200u);
  EXPECT_GT(j.at("handles")[0].at("region").at("vertices").size(), 3u);
  const auto& m = j.at("handles")[0].at("transform").at("matrix");
  EXPECT_GT(std::abs(m[2][3].get<double>()), 0.05);  // moved up (+z) on screen

  // `freeform deform` replays it.
  const std::string cmd = std::string(FREEFORM_CLI_PATH) + " deform '" + input.string() + "' --edit '" + edit.string() +
                          "' -o '" + replay.string() + "' > '" + (dir.path() / "deform.log").string() + "' 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "freeform deform failed; log: " << (dir.path() / "deform.log");
  const TriangleSoup a = read_mesh(saved.string()).soup, b = read_mesh(replay.string()).soup;
  const TriangleSoup original = read_mesh(input.string()).soup;
  ASSERT_EQ(a.positions.size(), b.positions.size());
  ASSERT_EQ(a.faces, b.faces);
  const double diag = bbox_diagonal(original);
  double diff = 0, moved = 0;
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    diff = std::max(diff, (a.positions[i] - b.positions[i]).norm());
    moved = std::max(moved, (a.positions[i] - original.positions[i]).norm());
  }
  EXPECT_LE(diff, 1e-9 * diag);
  EXPECT_GT(moved, 0.02 * diag);  // the drag really deformed the mesh
}

}  // namespace
}  // namespace freeform
