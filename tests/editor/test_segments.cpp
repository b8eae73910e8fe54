// Boundary smoothness segments in the editor model (issue 15): painting a stretch of the band,
// its value, undo/redo, the display against deform() of the exported edit, import, sessions.
#include "editor/document.h"
#include "editor_test_util.h"

#include "freeform/bcm/boundary_band.h"
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

namespace freeform::editor {
namespace {

using test_util::disc;

std::vector<Vertex> right_of(const Mesh& m, double x) {
  std::vector<Vertex> out;
  for (Vertex v : m.vertices())
    if (m.position(v).x() > x) out.push_back(v);
  return out;
}

std::vector<Vertex> intersect(std::vector<Vertex> a, std::vector<Vertex> b) {
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  std::vector<Vertex> out;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

bool bitwise_equal(const VertexData<Vec3>& a, const VertexData<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.raw().data(), b.raw().data(), a.size() * sizeof(Vec3)) == 0;
}

// k = 3 on a bumpy plane opened from `path`: a support disc with a lifted handle in its middle.
void setup(Document& doc, const std::string& path) {
  write_mesh(path, make_bumpy_plane(20, 20, 0.05, 2.0));
  doc.open(path);
  const Mesh& m = doc.rest_mesh();
  EditParameters p;
  p.settings.order = 3;
  p.multiresolution = false;
  doc.set_parameters(p);
  doc.set_region(PaintMode::Support, disc(m, Vec3(0.5, 0.5, 0), 0.4), false);
  doc.set_region(PaintMode::Handle, disc(m, Vec3(0.5, 0.5, 0), 0.1), false);
  const int id = doc.active_handle();
  Manipulator lift;
  lift.translation = Vec3(0, 0, 0.25);
  doc.commit_manipulator(id, doc.state().find_handle(id)->manipulator, lift);
}

TEST(Segments, PaintValueUndoRedo) {
  test::ScratchDir dir;
  Document doc;
  setup(doc, (dir / "plane.obj").string());
  const Mesh& m = doc.rest_mesh();
  const std::vector<Vertex> band = doc.smoothness_band();
  const Regions regions = doc.state().regions(m);
  EXPECT_EQ(band, smoothness_band(m, regions, 3));
  ASSERT_FALSE(band.empty());
  for (Vertex v : band) EXPECT_NE(regions.role(v), Role::Free);

  // A stroke over everything right of x = 0.6 paints only the band there, into a new C0 segment.
  const std::size_t steps = doc.history().undo_size();
  doc.begin_stroke(PaintMode::Boundary, false);
  const std::vector<Vertex> right = right_of(m, 0.6);
  doc.stroke(right);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments.size(), 1u);  // live while painting
  doc.end_stroke();
  EXPECT_EQ(doc.history().undo_size(), steps + 1);
  EXPECT_EQ(doc.history().next_undo()->label, "paint smoothness segment");
  ASSERT_EQ(doc.parameters().settings.smoothness.segments.size(), 1u);
  EXPECT_EQ(doc.active_segment(), 0);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 0.0);
  const std::vector<Vertex> stretch = intersect(band, right);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].vertices, stretch);

  doc.set_segment_value(0, 1.0);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 1.0);
  doc.set_segment_value(0, 7.0);  // clamped to k - 1
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 2.0);
  doc.undo();
  doc.undo();
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 0.0);
  doc.undo();
  EXPECT_TRUE(doc.parameters().settings.smoothness.segments.empty());
  EXPECT_EQ(doc.active_segment(), -1);
  doc.redo();
  doc.redo();
  ASSERT_EQ(doc.parameters().settings.smoothness.segments.size(), 1u);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 1.0);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].vertices, stretch);

  // Erasing part of it, then all of it: the empty segment goes away.
  doc.set_active_segment(0);
  doc.set_region(PaintMode::Boundary, right_of(m, 0.75), true);
  ASSERT_EQ(doc.parameters().settings.smoothness.segments.size(), 1u);
  std::vector<Vertex> kept;
  for (Vertex v : stretch)
    if (m.position(v).x() <= 0.75) kept.push_back(v);
  ASSERT_FALSE(kept.empty());
  ASSERT_LT(kept.size(), stretch.size());
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].vertices, kept);
  doc.set_region(PaintMode::Boundary, right, true);
  EXPECT_TRUE(doc.parameters().settings.smoothness.segments.empty());
  EXPECT_EQ(doc.active_segment(), -1);
  doc.undo();
  EXPECT_EQ(doc.parameters().settings.smoothness.segments.size(), 1u);
  // A stroke outside the band paints nothing and records no step.
  const std::size_t before = doc.history().undo_size();
  doc.set_active_segment(-1);
  doc.set_region(PaintMode::Boundary, disc(m, Vec3(0.02, 0.02, 0), 0.06), false);  // a far corner
  EXPECT_EQ(doc.history().undo_size(), before);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments.size(), 1u);
  doc.delete_segment(0);
  EXPECT_TRUE(doc.parameters().settings.smoothness.segments.empty());
  EXPECT_THROW(doc.delete_segment(0), InvalidInput);
  EXPECT_THROW(doc.set_segment_value(0, 1.0), InvalidInput);
  EXPECT_THROW(doc.set_active_segment(3), InvalidInput);
}

TEST(Segments, DisplayExportImportAndSession) {
  test::ScratchDir dir;
  Document doc;
  setup(doc, (dir / "plane.obj").string());
  const Mesh& m = doc.rest_mesh();
  doc.wait_for_precompute();
  const VertexData<Vec3> uniform = doc.display_positions();
  doc.set_region(PaintMode::Boundary, right_of(m, 0.6), false);
  doc.set_segment_value(0, 1.0);  // k = 3, c = 1: the unsymmetric case
  doc.wait_for_precompute();
  ASSERT_TRUE(doc.solver_current());
  EXPECT_FALSE(doc.solver()->solver().stats().bcm.symmetric);
  const VertexData<Vec3> shown = doc.display_positions();
  EXPECT_FALSE(bitwise_equal(shown, uniform));  // the segment changed the surface

  // The exported edit carries the segment and replays the display bit for bit.
  const std::string edit_path = (dir / "edit.json").string();
  doc.export_edit(edit_path);
  std::ifstream in(edit_path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_NE(text.str().find("\"segments\""), std::string::npos);
  const Edit edit = read_edit_file(edit_path, m);
  ASSERT_EQ(edit.settings.smoothness.segments.size(), 1u);
  EXPECT_EQ(edit.settings.smoothness.segments[0], doc.parameters().settings.smoothness.segments[0]);
  EXPECT_TRUE(bitwise_equal(deform(m, edit).positions(), shown));

  // Import restores it after a clear; a session round trip keeps it too.
  const EditParameters params = doc.parameters();
  doc.clear_regions();
  doc.set_parameters(EditParameters{});
  doc.import_edit(edit_path);
  EXPECT_EQ(doc.parameters(), params);
  const std::string session = (dir / "session.json").string();
  doc.save_session(session);
  Document other;
  other.load_session(session);
  EXPECT_EQ(other.state(), doc.state());
  other.wait_for_precompute();
  EXPECT_TRUE(bitwise_equal(other.display_positions(), shown));

  // Lowering the order clamps the segment's value; the band shrinks to one ring.
  EditParameters k2 = doc.parameters();
  k2.settings.order = 2;
  doc.set_parameters(k2);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 1.0);
  k2.settings.smoothness.segments[0].value = 5.0;
  doc.set_parameters(k2);
  EXPECT_EQ(doc.parameters().settings.smoothness.segments[0].value, 1.0);
  EXPECT_LT(doc.smoothness_band().size(), smoothness_band(m, doc.state().regions(m), 3).size());
}

}  // namespace
}  // namespace freeform::editor
