// The tool controller over a Document: the key sequence (G, X, typed 2.5, Enter), gizmo
// drags, brush/lasso painting and their undo steps, on a plane seen head-on.
#include "editor/tool_controller.h"

#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace freeform::editor {
namespace {

class ToolControllerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    doc.open_mesh(Mesh::from_soup(make_plane(20, 20, 2.0, 2.0)));
    view.width = 400;
    view.height = 400;
    view.camera.eye = Vec3(1, 1, 4);
    view.camera.target = Vec3(1, 1, 0);
    view.camera.up = Vec3(0, 1, 0);
    view.camera.fov_y_deg = 40;
    view.camera.z_near = 0.1;
    view.camera.z_far = 10;
  }

  // Support = everything, one movable handle = the vertices within 0.25 of the centre.
  int paint_support_and_handle() {
    std::vector<Vertex> all, handle;
    for (Vertex v : doc.rest_mesh().vertices()) {
      all.push_back(v);
      if ((doc.rest_mesh().position(v) - Vec3(1, 1, 0)).norm() <= 0.25) handle.push_back(v);
    }
    doc.set_region(PaintMode::Support, all, false);
    doc.set_region(PaintMode::Handle, handle, false);
    doc.wait_for_precompute();
    EXPECT_TRUE(doc.solver_current()) << doc.last_error();
    return doc.active_handle();
  }

  Eigen::Vector2d pixel_of(const Vec3& p) const { return view.project(p)->head<2>(); }

  Document doc;
  ScreenView view;
};

TEST_F(ToolControllerTest, GrabAlongXTypedAmountConfirmedWithEnter) {
  const int id = paint_support_and_handle();
  ASSERT_GE(id, 0);
  const Manipulator start = doc.state().find_handle(id)->manipulator;
  ToolController tools(doc);
  tools.set_view(view);
  tools.mouse_move({200, 200});
  ASSERT_TRUE(tools.key(Key::G, {}));
  EXPECT_TRUE(tools.transforming());
  ASSERT_TRUE(tools.key(Key::X, {}));
  for (char c : std::string("2.5")) ASSERT_TRUE(tools.character(c));
  EXPECT_NE(tools.transform_status().find("2.5"), std::string::npos) << tools.transform_status();
  ASSERT_TRUE(tools.key(Key::Enter, {}));
  EXPECT_FALSE(tools.transforming());

  const Manipulator& m = doc.state().find_handle(id)->manipulator;
  EXPECT_EQ(m.translation, start.translation + Vec3(2.5, 0, 0));
  EXPECT_TRUE(m.rotation.isApprox(start.rotation, 0.0));
  EXPECT_EQ(m.scale, start.scale);
  // The handle moved rigidly by (2.5, 0, 0) on screen too.
  doc.update_display();
  for (Vertex v : doc.state().handle_vertices(id))
    EXPECT_NEAR((doc.display_positions()[v] - doc.rest_mesh().position(v) - Vec3(2.5, 0, 0)).norm(), 0.0, 1e-12);
  // One undo step brings it back exactly.
  ASSERT_TRUE(doc.can_undo());
  doc.undo();
  EXPECT_EQ(doc.state().find_handle(id)->manipulator.translation, start.translation);
}

TEST_F(ToolControllerTest, EscapeAndRightClickCancelWithoutAStep) {
  const int id = paint_support_and_handle();
  const Manipulator start = doc.state().find_handle(id)->manipulator;
  const std::size_t steps = doc.history().undo_size();
  ToolController tools(doc);
  tools.set_view(view);
  tools.mouse_move({260, 200});  // the handle's centre projects to (200, 200)
  ASSERT_TRUE(tools.key(Key::R, {}));
  tools.mouse_move({200, 140});
  EXPECT_FALSE(doc.state().find_handle(id)->manipulator.rotation.isApprox(start.rotation, 1e-9));  // live preview
  ASSERT_TRUE(tools.key(Key::Escape, {}));
  EXPECT_TRUE(doc.state().find_handle(id)->manipulator.rotation.isApprox(start.rotation, 0.0));
  EXPECT_EQ(doc.state().find_handle(id)->manipulator.translation, start.translation);

  ASSERT_TRUE(tools.key(Key::S, {}));
  tools.mouse_move({300, 300});
  ASSERT_TRUE(tools.mouse_down(MouseButton::Right, {300, 300}, {}));
  EXPECT_EQ(doc.state().find_handle(id)->manipulator.scale, start.scale);
  EXPECT_EQ(doc.history().undo_size(), steps);
}

TEST_F(ToolControllerTest, GizmoCentreDragFollowsTheMouse) {
  const int id = paint_support_and_handle();
  ToolController tools(doc);
  tools.set_view(view);
  const auto shape = tools.gizmo();
  ASSERT_TRUE(shape.has_value());
  const Eigen::Vector2d c = shape->center;
  EXPECT_NEAR((c - pixel_of(doc.handle_pivot(id))).norm(), 0.0, 1e-6);
  ASSERT_TRUE(tools.mouse_down(MouseButton::Left, c, {}));
  tools.mouse_move(c + Eigen::Vector2d(15, 0));
  ASSERT_TRUE(tools.mouse_up(MouseButton::Left, c + Eigen::Vector2d(30, -10)));
  const Manipulator& m = doc.state().find_handle(id)->manipulator;
  const Vec3 centre = *m.pivot + m.translation;
  EXPECT_NEAR((pixel_of(centre) - (c + Eigen::Vector2d(30, -10))).norm(), 0.0, 1e-6);
  EXPECT_NEAR(m.translation.z(), 0.0, 1e-12);  // in the view plane, which is z = 0 here
  EXPECT_GT(m.translation.x(), 0.0);
  EXPECT_GT(m.translation.y(), 0.0);  // screen up = +y
}

TEST_F(ToolControllerTest, BrushStrokeIsOneStepOverTheCircle) {
  ToolController tools(doc);
  tools.set_view(view);
  tools.options.brush_radius_px = 50;
  const Eigen::Vector2d a(150, 200), b(250, 200);
  ASSERT_TRUE(tools.mouse_down(MouseButton::Left, a, {}));
  EXPECT_TRUE(tools.stroking());
  tools.mouse_move(b);
  ASSERT_TRUE(tools.mouse_up(MouseButton::Left, b));
  // Expected: every vertex within 50 px of the segment a-b (a plane seen head-on: all visible).
  std::set<int> expected;
  for (Vertex v : doc.rest_mesh().vertices()) {
    const Eigen::Vector2d p = pixel_of(doc.rest_mesh().position(v));
    const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    if ((p - (a + s * (b - a))).norm() <= 50 - 1e-6) expected.insert(v.idx());
  }
  std::set<int> painted;
  for (Vertex v : doc.state().support_vertices()) painted.insert(v.idx());
  for (int v : expected) EXPECT_TRUE(painted.count(v)) << v;
  // Dabs are half a radius apart: nothing farther than the radius from the segment.
  for (int v : painted) {
    const Eigen::Vector2d p = pixel_of(doc.rest_mesh().position(Vertex(v)));
    const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    EXPECT_LE((p - (a + s * (b - a))).norm(), 50 + 1e-6) << v;
  }
  EXPECT_EQ(doc.history().undo_size(), 1u);
  doc.undo();
  EXPECT_EQ(doc.state().n_support(), 0);
}

TEST_F(ToolControllerTest, CtrlLassoRemovesInsidePolygon) {
  std::vector<Vertex> all;
  for (Vertex v : doc.rest_mesh().vertices()) all.push_back(v);
  doc.set_region(PaintMode::Support, all, false);
  ToolController tools(doc);
  tools.set_view(view);
  tools.options.tool = Tool::Lasso;
  Modifiers ctrl;
  ctrl.ctrl = true;
  ASSERT_TRUE(tools.mouse_down(MouseButton::Left, {100, 100}, ctrl));
  tools.mouse_move({300, 100});
  tools.mouse_move({300, 300});
  tools.mouse_move({100, 300});
  ASSERT_TRUE(tools.mouse_up(MouseButton::Left, {100, 300}));
  for (Vertex v : doc.rest_mesh().vertices()) {
    const Eigen::Vector2d p = pixel_of(doc.rest_mesh().position(v));
    const bool inside = p.x() > 100 + 1e-6 && p.x() < 300 - 1e-6 && p.y() > 100 + 1e-6 && p.y() < 300 - 1e-6;
    const bool outside = p.x() < 100 - 1e-6 || p.x() > 300 + 1e-6 || p.y() < 100 - 1e-6 || p.y() > 300 + 1e-6;
    if (inside) {
      EXPECT_FALSE(doc.state().in_support(v)) << v.idx();
    }
    if (outside) {
      EXPECT_TRUE(doc.state().in_support(v)) << v.idx();
    }
  }
}

TEST_F(ToolControllerTest, GrowAddsOneRing) {
  const Vertex centre(10 * 21 + 10);
  doc.set_region(PaintMode::Support, std::vector<Vertex>{centre}, false);
  ToolController tools(doc);
  tools.grow();
  // Interior vertex of the alternating-diagonal grid: 6 neighbours.
  EXPECT_EQ(doc.state().n_support(), 1 + static_cast<int>(doc.rest_mesh().valence(centre)));
  tools.shrink();
  EXPECT_EQ(doc.state().n_support(), 1);
}

TEST_F(ToolControllerTest, BracketsAndWheelResizeTheBrush) {
  ToolController tools(doc);
  const double r = tools.options.brush_radius_px;
  EXPECT_TRUE(tools.key(Key::BracketRight, {}));
  EXPECT_GT(tools.options.brush_radius_px, r);
  EXPECT_TRUE(tools.key(Key::BracketLeft, {}));
  EXPECT_NEAR(tools.options.brush_radius_px, r, 1e-12);
  EXPECT_TRUE(tools.scroll(-1, {}));
  EXPECT_LT(tools.options.brush_radius_px, r);
  Modifiers ctrl;
  ctrl.ctrl = true;
  EXPECT_FALSE(tools.scroll(1, ctrl));  // Ctrl+wheel goes to the camera
}

}  // namespace
}  // namespace freeform::editor
