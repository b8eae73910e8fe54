#include "editor/tool_controller.h"

#include "editor/region_ops.h"
#include "freeform/mesh/bounds.h"

#include <algorithm>
#include <cmath>

namespace freeform::editor {
namespace {

bool same_view(const ScreenView& a, const ScreenView& b) {
  return a.width == b.width && a.height == b.height && a.camera.eye == b.camera.eye &&
         a.camera.target == b.camera.target && a.camera.up == b.camera.up && a.camera.fov_y_deg == b.camera.fov_y_deg;
}

}  // namespace

ToolController::ToolController(Document& document) : doc_(document) {}

void ToolController::set_view(const ScreenView& view) {
  view_ = view;
  have_view_ = true;
  if (modal_) modal_->set_view(view);
}

void ToolController::reset() {
  bvh_.reset();
  picker_.reset();
  bvh_mesh_ = nullptr;
  modal_.reset();
  drag_.reset();
  stroke_active_ = false;
  lasso_.clear();
}

const ScreenPicker& ToolController::picker() {
  const Mesh& mesh = doc_.rest_mesh();
  const VertexData<Vec3>& positions = doc_.display_positions();
  const std::uint64_t version = doc_.display_version();
  if (!bvh_ || bvh_mesh_ != &mesh || bvh_->n_faces() != mesh.n_faces()) {
    bvh_ = std::make_unique<Bvh>(mesh, positions);
    bvh_mesh_ = &mesh;
    bvh_version_ = version;
    picker_.reset();
  } else if (bvh_version_ != version) {
    bvh_->refit(positions);
    bvh_version_ = version;
    picker_.reset();
  }
  if (!picker_ || picker_version_ != version || !same_view(picker_view_, view_)) {
    picker_ = std::make_unique<ScreenPicker>(mesh, positions, *bvh_, view_);
    picker_view_ = view_;
    picker_version_ = version;
  }
  return *picker_;
}

std::optional<int> ToolController::active_movable() const {
  const int id = doc_.active_handle();
  const HandleState* h = doc_.state().find_handle(id);
  if (!h || !h->movable) return std::nullopt;
  return id;
}

// The modal tools assume the handle's centre is pivot + t. That holds for a manipulator about
// the rest centroid; a handle with an imported matrix is recentred at the matrix image of its
// centroid first (the same affine map, to rounding).
Manipulator ToolController::centred_manipulator(int id, Vec3* pivot) const {
  const HandleState& h = *doc_.state().find_handle(id);
  Manipulator m = h.manipulator;
  if (h.matrix) {  // imported matrices only: the centroid's image, recomputed (O(#V))
    m = recentred(m, *h.matrix * centroid(doc_.rest_mesh(), doc_.state().handle_vertices(id)));
  } else {
    m.pivot = doc_.handle_pivot(id);  // the stored pivot: no scan of the mesh per frame
  }
  *pivot = *m.pivot;
  return m;
}

std::optional<GizmoShape> ToolController::gizmo() const {
  if (!have_view_) return std::nullopt;
  const auto id = active_movable();
  if (!id || doc_.state().handle_size(*id) == 0) return std::nullopt;
  Vec3 pivot;
  const Manipulator m = centred_manipulator(*id, &pivot);
  GizmoShape shape = gizmo_shape(view_, pivot + m.translation, m.rotation, 100.0, hovered_);
  if (!shape.visible) return std::nullopt;
  return shape;
}

std::string ToolController::transform_status() const {
  if (modal_) return modal_->status();
  if (drag_) return drag_->transform().status();
  return {};
}

double ToolController::flood_radius() const {
  if (options.flood_radius > 0.0) return options.flood_radius;
  return 0.08 * bounding_diagonal(doc_.display_positions());
}

void ToolController::paint(const std::vector<Vertex>& vertices, bool remove) {
  if (!vertices.empty()) doc_.set_region(options.mode, vertices, remove);
}

std::vector<Vertex> ToolController::region_vertices() const {
  const EditState& s = doc_.state();
  if (options.mode == PaintMode::Support) return s.support_vertices();
  if (options.mode == PaintMode::Boundary) {
    const int seg = doc_.active_segment();
    return seg < 0 ? std::vector<Vertex>{} : s.parameters().settings.smoothness.segments[static_cast<std::size_t>(seg)].vertices;
  }
  const HandleState* h = s.find_handle(doc_.active_handle());
  if (!h || h->movable != (options.mode == PaintMode::Handle)) return {};
  return s.handle_vertices(h->id);
}

void ToolController::dab(const Eigen::Vector2d& px) {
  // Dabs along the segment from the last one, half a radius apart, so fast strokes stay closed.
  const double r = options.brush_radius_px;
  const Eigen::Vector2d from = last_dab_.value_or(px);
  const int steps = std::max(1, static_cast<int>(std::ceil((px - from).norm() / (0.5 * r))));
  const ScreenPicker& p = picker();
  for (int i = 1; i <= steps; ++i) {
    const Eigen::Vector2d c = from + (px - from) * (static_cast<double>(i) / steps);
    const std::vector<Vertex> vs = p.brush(c, r);
    if (!vs.empty()) doc_.stroke(vs);
  }
  last_dab_ = px;
}

bool ToolController::start_modal(TransformKind kind) {
  const auto id = active_movable();
  if (!id || !cursor_ || !have_view_ || doc_.state().handle_size(*id) == 0) return false;
  Vec3 pivot;
  transform_start_ = doc_.state().find_handle(*id)->manipulator;
  const Manipulator centred = centred_manipulator(*id, &pivot);
  modal_ = std::make_unique<ModalTransform>(kind, centred, pivot, view_, *cursor_);
  transform_handle_ = *id;
  return true;
}

void ToolController::preview() {
  if (modal_) doc_.preview_manipulator(transform_handle_, modal_->current());
  if (drag_) doc_.preview_manipulator(transform_handle_, drag_->current());
}

void ToolController::finish_transform(bool confirm) {
  Manipulator final_m = transform_start_;
  if (confirm) final_m = modal_ ? modal_->confirm() : drag_->current();
  modal_.reset();
  drag_.reset();
  if (confirm) doc_.commit_manipulator(transform_handle_, transform_start_, final_m);
  else doc_.preview_manipulator(transform_handle_, transform_start_);
  transform_handle_ = -1;
}

bool ToolController::mouse_down(MouseButton button, const Eigen::Vector2d& px, const Modifiers& mods) {
  cursor_ = px;
  if (modal_) {  // click confirms (left) or cancels (right)
    if (button == MouseButton::Left) finish_transform(true);
    else if (button == MouseButton::Right) finish_transform(false);
    return button != MouseButton::Middle;
  }
  if (button != MouseButton::Left || !have_view_ || drag_ || stroke_active_) return false;
  if (const auto shape = gizmo()) {
    const GizmoPart part = gizmo_hit(*shape, px);
    if (part != GizmoPart::None) {
      const int id = *active_movable();
      Vec3 pivot;
      transform_start_ = doc_.state().find_handle(id)->manipulator;
      const Manipulator centred = centred_manipulator(id, &pivot);
      drag_ = std::make_unique<GizmoDrag>(part, centred, pivot, view_, px);
      transform_handle_ = id;
      return true;
    }
  }
  const auto hit = picker().pick(px);
  if (mods.alt) {  // select the handle under the cursor
    if (!hit) return false;
    const int id = doc_.state().handle_of(hit->vertex);
    if (id >= 0) doc_.set_active_handle(id);
    return true;
  }
  switch (options.tool) {
    case Tool::Brush:
      if (!hit) return false;  // empty background: the camera orbits
      doc_.begin_stroke(options.mode, mods.ctrl);
      stroke_active_ = true;
      last_dab_.reset();
      dab(px);
      return true;
    case Tool::Lasso:
      lasso_.assign(1, px);
      lasso_remove_ = mods.ctrl;
      return true;
    case Tool::Flood:
      if (!hit) return false;
      paint(geodesic_flood(doc_.rest_mesh(), doc_.display_positions(), hit->vertex, flood_radius()), mods.ctrl);
      return true;
  }
  return false;
}

bool ToolController::mouse_move(const Eigen::Vector2d& px) {
  cursor_ = px;
  if (modal_) {
    modal_->move_mouse(px);
    preview();
    return true;
  }
  if (drag_) {
    drag_->move_mouse(px);
    preview();
    return true;
  }
  if (stroke_active_) {
    dab(px);
    return true;
  }
  if (!lasso_.empty()) {
    if ((px - lasso_.back()).norm() >= 2.0) lasso_.push_back(px);
    return true;
  }
  const auto shape = gizmo();
  hovered_ = shape ? gizmo_hit(*shape, px) : GizmoPart::None;
  return false;
}

bool ToolController::mouse_up(MouseButton button, const Eigen::Vector2d& px) {
  cursor_ = px;
  if (button != MouseButton::Left) return modal_ != nullptr;
  if (drag_) {
    drag_->move_mouse(px);
    finish_transform(true);
    return true;
  }
  if (stroke_active_) {
    stroke_active_ = false;
    last_dab_.reset();
    doc_.end_stroke();
    return true;
  }
  if (!lasso_.empty()) {
    std::vector<Eigen::Vector2d> polygon;
    polygon.swap(lasso_);
    if (polygon.size() >= 3) paint(picker().lasso(polygon), lasso_remove_);
    return true;
  }
  return false;
}

bool ToolController::scroll(double dy, const Modifiers& mods) {
  if (options.tool != Tool::Brush || mods.ctrl || transforming()) return false;
  options.brush_radius_px = std::clamp(options.brush_radius_px * std::pow(1.15, dy), 2.0, 400.0);
  return true;
}

bool ToolController::key(Key k, const Modifiers& mods) {
  if (modal_) {
    switch (k) {
      case Key::X: modal_->press_axis(0); break;
      case Key::Y: modal_->press_axis(1); break;
      case Key::Z: modal_->press_axis(2); break;
      case Key::Backspace: modal_->backspace(); break;
      case Key::Enter: finish_transform(true); return true;
      case Key::Escape: finish_transform(false); return true;
      default: return true;  // G / R / S and brackets are ignored during a transform
    }
    preview();
    return true;
  }
  if (drag_ || stroke_active_ || mods.ctrl || mods.alt) return false;
  switch (k) {
    case Key::G: return start_modal(TransformKind::Grab);
    case Key::R: return start_modal(TransformKind::Rotate);
    case Key::S: return start_modal(TransformKind::Scale);
    case Key::BracketLeft: options.brush_radius_px = std::max(2.0, options.brush_radius_px / 1.15); return true;
    case Key::BracketRight: options.brush_radius_px = std::min(400.0, options.brush_radius_px * 1.15); return true;
    default: return false;
  }
}

bool ToolController::character(char c) {
  if (!modal_) return false;
  const bool used = modal_->type_char(c);
  if (used) preview();
  return used;
}

void ToolController::grow() {
  const std::vector<Vertex> region = region_vertices();
  if (region.empty()) return;
  paint(grow_rings(doc_.rest_mesh(), region, options.rings), false);
}

void ToolController::shrink() {
  const std::vector<Vertex> region = region_vertices();
  if (region.empty()) return;
  const std::vector<Vertex> kept = shrink_rings(doc_.rest_mesh(), region, options.rings);
  std::vector<Vertex> removed;
  std::set_difference(region.begin(), region.end(), kept.begin(), kept.end(), std::back_inserter(removed));
  paint(removed, true);
}

}  // namespace freeform::editor
