// The editor's tools between the widgets and the camera (GL-free): mouse and key events that
// the UI did not take go here first; what this returns false for goes to the camera.
//
//   brush   left drag paints the vertices under the circle (visible surface only); Shift adds
//           (the default), Ctrl removes; [ ] or the mouse wheel change the radius (Ctrl+wheel
//           zooms instead). One stroke = one undo step.
//   lasso   left drag draws a polygon; on release the visible vertices inside are painted.
//   flood   left click paints the vertices within the flood radius (edge-path distance on the
//           displayed surface) of the clicked point.
//   any     Alt+left click selects the handle under the cursor. A left press on the gizmo of
//           the active movable handle drags it (translate arrows, rotate rings, scale boxes,
//           free centre). G / R / S start a grab / rotate / scale of the active handle at the
//           cursor; X / Y / Z lock an axis (again: local axis), digits type the amount, Enter
//           or a left click confirms, Esc or a right click cancels. One move = one undo step.
//
// The paint mode (support / handle / immovable) says what a stroke paints (Document).
#pragma once

#include "editor/bvh.h"
#include "editor/document.h"
#include "editor/gizmo.h"
#include "editor/modal_transform.h"
#include "editor/picking.h"
#include "editor/screen.h"

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace freeform::editor {

enum class Tool { Brush, Lasso, Flood };
enum class MouseButton { Left, Middle, Right };
enum class Key { G, R, S, X, Y, Z, Enter, Escape, Backspace, BracketLeft, BracketRight };

struct Modifiers {
  bool shift = false;
  bool ctrl = false;
  bool alt = false;
};

struct ToolOptions {
  Tool tool = Tool::Brush;
  PaintMode mode = PaintMode::Support;
  double brush_radius_px = 40.0;  // [2, 400]
  double flood_radius = 0.0;      // world units; <= 0: 8% of the bounding-box diagonal
  int rings = 1;                  // grow / shrink step
};

class ToolController {
 public:
  explicit ToolController(Document& document);

  ToolOptions options;

  // The camera and viewport of this frame; call before the frame's events.
  void set_view(const ScreenView& view);
  // The mesh was replaced (open, session load): drop cached picking structures.
  void reset();

  // Each returns true if the tool used the event (the camera must then ignore it).
  bool mouse_down(MouseButton button, const Eigen::Vector2d& px, const Modifiers& mods);
  bool mouse_move(const Eigen::Vector2d& px);
  bool mouse_up(MouseButton button, const Eigen::Vector2d& px);
  bool scroll(double dy, const Modifiers& mods);
  bool key(Key key, const Modifiers& mods);
  bool character(char c);  // typed amount while a G / R / S transform runs

  // Panel actions on the region of the current paint mode (support, active handle or segment).
  void grow();
  void shrink();

  // --- for the overlays and the status line ---
  std::optional<Eigen::Vector2d> cursor() const { return cursor_; }
  bool stroking() const { return stroke_active_; }
  const std::vector<Eigen::Vector2d>& lasso_points() const { return lasso_; }
  // The gizmo of the active movable handle (nullopt if there is none or it is off screen).
  std::optional<GizmoShape> gizmo() const;
  bool transforming() const { return modal_ != nullptr || drag_ != nullptr; }
  std::string transform_status() const;  // "" when no transform runs
  double flood_radius() const;           // resolved (options.flood_radius or the default)

 private:
  Document& doc_;
  ScreenView view_;
  bool have_view_ = false;
  std::optional<Eigen::Vector2d> cursor_;
  GizmoPart hovered_ = GizmoPart::None;

  // Picking caches: the BVH follows the displayed positions (refit), the picker the view.
  std::unique_ptr<Bvh> bvh_;
  const Mesh* bvh_mesh_ = nullptr;
  std::uint64_t bvh_version_ = 0;
  std::unique_ptr<ScreenPicker> picker_;
  ScreenView picker_view_;
  std::uint64_t picker_version_ = 0;

  bool stroke_active_ = false;
  std::optional<Eigen::Vector2d> last_dab_;
  std::vector<Eigen::Vector2d> lasso_;
  bool lasso_remove_ = false;

  std::unique_ptr<ModalTransform> modal_;
  std::unique_ptr<GizmoDrag> drag_;
  int transform_handle_ = -1;
  Manipulator transform_start_;

  const ScreenPicker& picker();
  void dab(const Eigen::Vector2d& px);
  void paint(const std::vector<Vertex>& vertices, bool remove);
  // The region of the paint mode: the support, the active handle of that kind, or the active segment.
  std::vector<Vertex> region_vertices() const;
  // Active movable handle: its id, its manipulator recentred so that pivot + t is its centre.
  std::optional<int> active_movable() const;
  Manipulator centred_manipulator(int id, Vec3* pivot) const;
  bool start_modal(TransformKind kind);
  void finish_transform(bool confirm);
  void preview();
};

}  // namespace freeform::editor
