// Screen-space overlays drawn with ImGui's background draw list (above the mesh, below the
// panel): the brush circle at the cursor, the lasso polyline, the manipulator gizmo and the
// running transform's status; and the region colours of the mesh (viewer/region_colors.h
// palette: support blue, movable handles green, fixed gray, immovable handles darker gray,
// the active handle brighter; the smoothness band by c, the active segment brighter).
#include "app.h"

#include "freeform/bcm/boundary_band.h"
#include "viewer/region_colors.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>

namespace freeform::editor {
namespace {

ImU32 color(const GizmoColor& c, float alpha_scale = 1.0f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, c.a * alpha_scale));
}

viewer::Rgb brighter(const viewer::Rgb& c, float amount) {
  return {c[0] + (1.0f - c[0]) * amount, c[1] + (1.0f - c[1]) * amount, c[2] + (1.0f - c[2]) * amount};
}

ImU32 mode_color(PaintMode mode, bool erase) {
  if (erase) return IM_COL32(230, 80, 70, 255);
  switch (mode) {
    case PaintMode::Support: return IM_COL32(60, 110, 245, 255);
    case PaintMode::Handle: return IM_COL32(40, 170, 60, 255);
    case PaintMode::Immovable: return IM_COL32(90, 90, 90, 255);
    case PaintMode::Boundary: return IM_COL32(235, 150, 20, 255);
  }
  return IM_COL32(255, 255, 255, 255);
}

}  // namespace

bool App::band_shown() const {
  return doc_.has_mesh() && doc_.parameters().settings.order > 1 &&
         (tools_.options.mode == PaintMode::Boundary || !doc_.parameters().settings.smoothness.segments.empty());
}

void App::recolor() {
  shown_region_version_ = doc_.region_version();
  shown_active_handle_ = doc_.active_handle();
  shown_band_ = band_shown();
  shown_active_segment_ = doc_.active_segment();
  if (!doc_.has_mesh() || scene_.n_vertices() != doc_.state().n_vertices()) return;
  const viewer::RegionPalette palette;
  const EditState& st = doc_.state();
  const int active = doc_.active_handle();
  std::vector<viewer::Rgb> colors(static_cast<std::size_t>(st.n_vertices()), palette.fixed);
  std::vector<bool> movable_by_id(static_cast<std::size_t>(std::max(st.next_handle_id(), 0)), true);
  for (const HandleState& h : st.handles())
    if (h.id >= 0 && h.id < static_cast<int>(movable_by_id.size())) movable_by_id[static_cast<std::size_t>(h.id)] = h.movable;
  const auto& flags = st.support_flags();
  const auto& ids = st.handle_ids();
  for (std::size_t v = 0; v < colors.size(); ++v) {
    const int h = ids[v];
    if (h >= 0) {
      const bool movable = h < static_cast<int>(movable_by_id.size()) ? movable_by_id[static_cast<std::size_t>(h)] : true;
      const viewer::Rgb base = movable ? palette.handle : palette.immovable;
      colors[v] = h == active ? brighter(base, movable ? 0.45f : 0.12f) : base;  // immovable: stay darker than fixed
    } else if (flags[v]) {
      colors[v] = palette.free;
    }
  }
  if (shown_band_ && doc_.regions_problem().empty()) {
    const Mesh& rest = doc_.rest_mesh();
    viewer::color_smoothness_band(colors, doc_.smoothness_band(), smoothness_per_vertex(st.regions(rest), st.settings()));
    const int seg = doc_.active_segment();  // the segment being edited stands out
    if (seg >= 0)
      for (Vertex v : st.parameters().settings.smoothness.segments[static_cast<std::size_t>(seg)].vertices)
        colors[static_cast<std::size_t>(v.idx())] = brighter(colors[static_cast<std::size_t>(v.idx())], 0.35f);
  }
  viewer::set_colors(scene_, colors);
}

void App::draw_overlays() {
  ImDrawList* dl = ImGui::GetBackgroundDrawList();
  const ImVec2 origin(static_cast<float>(layout_.x), static_cast<float>(layout_.y));
  const auto at = [&](const Eigen::Vector2d& p) { return ImVec2(origin.x + static_cast<float>(p.x()), origin.y + static_cast<float>(p.y())); };
  dl->PushClipRect(origin, ImVec2(origin.x + layout_.width, origin.y + layout_.height), false);
  if (!doc_.has_mesh()) {
    const char* hint = "Open a mesh: type its path in the panel, drop a file here, or pick a recent one";
    const ImVec2 size = ImGui::CalcTextSize(hint);
    dl->AddText(ImVec2(origin.x + 0.5f * (layout_.width - size.x), origin.y + 0.5f * (layout_.height - size.y)),
                IM_COL32(90, 90, 100, 255), hint);
    dl->PopClipRect();
    return;
  }
  const ToolOptions& opt = tools_.options;
  const bool erase = glfwGetKey(window_, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
                     glfwGetKey(window_, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;

  // The manipulator gizmo of the active movable handle.
  if (const std::optional<GizmoShape> g = tools_.gizmo(); g && g->visible) {
    for (const GizmoPolyline& line : g->rings) {
      std::vector<ImVec2> pts;
      pts.reserve(line.points.size());
      for (const auto& p : line.points) pts.push_back(at(p));
      dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), color(line.color), 0, line.thickness);
    }
    for (const GizmoPolyline& line : g->arms) {
      std::vector<ImVec2> pts;
      for (const auto& p : line.points) pts.push_back(at(p));
      dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), color(line.color), 0, line.thickness);
    }
    for (const GizmoTriangle& t : g->arrowheads)
      dl->AddTriangleFilled(at(t.corners[0]), at(t.corners[1]), at(t.corners[2]), color(t.color));
    for (const GizmoBox& b : g->boxes) {
      const Eigen::Vector2d h(b.half_size, b.half_size);
      dl->AddRectFilled(at(b.center - h), at(b.center + h), color(b.color));
    }
    dl->AddCircleFilled(at(g->center), static_cast<float>(g->center_radius), color(g->center_color, 0.35f), 24);
    dl->AddCircle(at(g->center), static_cast<float>(g->center_radius), color(g->center_color), 24, 2.0f);
  }

  // The lasso being drawn: the polyline and, dashed-looking and thinner, its closing edge.
  const auto& lasso = tools_.lasso_points();
  if (lasso.size() >= 2) {
    std::vector<ImVec2> pts;
    pts.reserve(lasso.size());
    for (const auto& p : lasso) pts.push_back(at(p));
    const ImU32 c = mode_color(opt.mode, erase);
    dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), c, 0, 2.0f);
    dl->AddLine(pts.back(), pts.front(), (c & 0x00FFFFFFu) | 0x80000000u, 1.0f);
  }

  // The brush circle (or the flood / lasso cursor) while the mouse is over the viewport.
  const bool camera_drag = drag_ == DragOwner::Orbit || drag_ == DragOwner::Pan;
  if (const auto cursor = tools_.cursor(); cursor && mouse_in_view_ && !camera_drag && !tools_.transforming()) {
    const ImU32 c = mode_color(opt.mode, erase);
    if (opt.tool == Tool::Brush) {
      const float r = static_cast<float>(opt.brush_radius_px);
      dl->AddCircle(at(*cursor), r, IM_COL32(255, 255, 255, 160), 48, 3.0f);
      dl->AddCircle(at(*cursor), r, c, 48, 1.5f);
    } else {
      dl->AddCircle(at(*cursor), 4.0f, c, 12, 2.0f);
    }
  }

  // The running G / R / S transform, next to the cursor.
  if (const std::string status = tools_.transform_status(); !status.empty()) {
    const ImVec2 p = at(to_viewport(mouse_) + Eigen::Vector2d(16, 16));
    dl->AddText(ImVec2(p.x + 1, p.y + 1), IM_COL32(255, 255, 255, 200), status.c_str());
    dl->AddText(p, IM_COL32(20, 20, 20, 255), status.c_str());
  }
  dl->PopClipRect();
}

}  // namespace freeform::editor
