// The side panel: File, View, Regions, Parameters, Edit. Built every frame before drawing;
// every change goes to the Document / ToolController / camera at once.
#include "app.h"

#include "freeform/edit/edit_report.h"
#include "viewer/region_colors.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <fmt/core.h>

#include <filesystem>
#include <iterator>

namespace freeform::editor {
namespace {

constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                    ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus;

void help_marker(const char* text) {
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

}  // namespace

void App::build_ui() {
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(layout_.panel_width, static_cast<float>(layout_.height)));
  if (ImGui::Begin("Freeform", nullptr, kFixed)) {
    ImGui::PushItemWidth(-10.0f * ImGui::GetFontSize());  // room for the labels
    panel_file();
    panel_view();
    panel_regions();
    panel_parameters();
    panel_edit();
    ImGui::PopItemWidth();
  }
  ImGui::End();
  status_line();
  popups();
}

void App::panel_file() {
  if (!ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::SetNextItemWidth(-1);
  if (ImGui::InputTextWithHint("##path", "mesh path (.obj .off .ply .stl .gltf .glb)", &path_field_,
                               ImGuiInputTextFlags_EnterReturnsTrue))
    open_mesh(path_field_);
  if (ImGui::Button("Open")) open_mesh(path_field_);
  help_marker("Open the mesh typed above (Enter in the field does the same; files can also be dropped on the window)");
  ImGui::SameLine();
  ImGui::BeginDisabled(!doc_.has_mesh());
  if (ImGui::Button("Save mesh")) save_mesh_shortcut();
  help_marker("Ctrl+S: write the displayed mesh to the last 'Save as' path (asks the first time)");
  ImGui::SameLine();
  if (ImGui::Button("Save as...")) prompt_save_as();
  help_marker("Ctrl+Shift+S");
  ImGui::EndDisabled();
  if (!recent_.entries().empty() && ImGui::TreeNodeEx("Recent", ImGuiTreeNodeFlags_DefaultOpen)) {
    std::string chosen;
    for (const std::string& path : recent_.entries()) {
      const std::string name = std::filesystem::path(path).filename().string();
      ImGui::PushID(path.c_str());
      if (ImGui::Selectable(name.c_str(), path == doc_.path())) chosen = path;
      help_marker(path.c_str());
      ImGui::PopID();
    }
    ImGui::TreePop();
    if (!chosen.empty()) {
      if (std::filesystem::exists(chosen)) {
        path_field_ = chosen;
        open_mesh(chosen);
      } else {
        recent_.remove(chosen);
        try {
          recent_.save();
        } catch (const std::exception&) {
        }
        error(chosen + " no longer exists; removed from the recent files");
      }
    }
  }
}

void App::panel_view() {
  if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
  const auto up = [this] { return up_axis_ == 0 ? viewer::UpAxis::Z : viewer::UpAxis::Y; };
  ImGui::BeginDisabled(!doc_.has_mesh());
  if (ImGui::Button("Fit (F)")) camera_.fit(scene_.bounds, aspect());
  help_marker("Frame the mesh, keeping the view direction");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(6.0f * ImGui::GetFontSize());
  if (ImGui::Combo("##preset", &view_preset_, kViewPresetNames, static_cast<int>(std::size(kViewPresetNames))))
    camera_.reset(scene_.bounds, kViewPresets[view_preset_], up(), aspect());
  ImGui::SameLine();
  if (ImGui::Button("Reset view")) camera_.reset(scene_.bounds, kViewPresets[view_preset_], up(), aspect());
  ImGui::EndDisabled();
  ImGui::TextUnformatted("Up axis");
  ImGui::SameLine();
  bool up_changed = ImGui::RadioButton("z", &up_axis_, 0);
  ImGui::SameLine();
  up_changed |= ImGui::RadioButton("y", &up_axis_, 1);
  if (up_changed && doc_.has_mesh()) camera_.reset(scene_.bounds, kViewPresets[view_preset_], up(), aspect());
  ImGui::TextUnformatted("Shading");
  ImGui::SameLine();
  int flat = draw_.flat ? 1 : 0;
  ImGui::RadioButton("smooth", &flat, 0);
  ImGui::SameLine();
  ImGui::RadioButton("flat", &flat, 1);
  draw_.flat = flat == 1;
  ImGui::SameLine();
  ImGui::Checkbox("wireframe", &draw_.wireframe);
}

void App::panel_regions() {
  if (!ImGui::CollapsingHeader("Regions", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::BeginDisabled(!doc_.has_mesh() || tools_.transforming());
  ToolOptions& opt = tools_.options;
  int tool = static_cast<int>(opt.tool), mode = static_cast<int>(opt.mode);
  ImGui::TextUnformatted("Tool");
  ImGui::SameLine(5.0f * ImGui::GetFontSize());
  ImGui::RadioButton("brush", &tool, static_cast<int>(Tool::Brush));
  help_marker("Left drag paints the visible vertices under the circle; Ctrl+drag erases; [ ] or the wheel: radius");
  ImGui::SameLine();
  ImGui::RadioButton("lasso", &tool, static_cast<int>(Tool::Lasso));
  help_marker("Left drag draws a polygon; the visible vertices inside are painted on release (Ctrl: erased)");
  ImGui::SameLine();
  ImGui::RadioButton("flood", &tool, static_cast<int>(Tool::Flood));
  help_marker("Left click paints every vertex within the flood radius (along the surface) of the clicked point");
  ImGui::TextUnformatted("Paint");
  ImGui::SameLine(5.0f * ImGui::GetFontSize());
  ImGui::RadioButton("support", &mode, static_cast<int>(PaintMode::Support));
  ImGui::SameLine();
  ImGui::RadioButton("handle", &mode, static_cast<int>(PaintMode::Handle));
  ImGui::SameLine();
  ImGui::RadioButton("immovable", &mode, static_cast<int>(PaintMode::Immovable));
  ImGui::NewLine();
  ImGui::SameLine(5.0f * ImGui::GetFontSize());
  ImGui::RadioButton("boundary smoothness segment", &mode, static_cast<int>(PaintMode::Boundary));
  help_marker("Paint a stretch of the boundary band (where smoothness acts) into the active smoothness segment");
  opt.tool = static_cast<Tool>(tool);
  opt.mode = static_cast<PaintMode>(mode);

  float radius = static_cast<float>(opt.brush_radius_px);
  if (ImGui::SliderFloat("brush radius", &radius, 2.0f, 400.0f, "%.0f px", ImGuiSliderFlags_Logarithmic))
    opt.brush_radius_px = radius;
  float flood = static_cast<float>(tools_.flood_radius());
  const float diag = doc_.has_mesh() ? static_cast<float>((scene_.bounds.max - scene_.bounds.min).norm()) : 1.0f;
  if (ImGui::SliderFloat("flood radius", &flood, 1e-3f * diag, 0.5f * diag, "%.4g", ImGuiSliderFlags_Logarithmic))
    opt.flood_radius = flood;
  help_marker("World units along the surface (default: 8% of the bounding-box diagonal)");
  ImGui::SetNextItemWidth(5.0f * ImGui::GetFontSize());
  ImGui::SliderInt("rings", &opt.rings, 1, 10);
  ImGui::SameLine();
  if (ImGui::Button("Grow")) attempt("grow", [&] { tools_.grow(); });
  help_marker("Grow the region of the paint mode (support, or the active handle) by the rings");
  ImGui::SameLine();
  if (ImGui::Button("Shrink")) attempt("shrink", [&] { tools_.shrink(); });
  ImGui::SameLine();
  if (ImGui::Button("Clear")) attempt("clear", [&] { doc_.clear_regions(); });
  help_marker("Remove the support and every handle (one undo step)");

  // Handles: select (the gizmo's target), delete, new.
  const auto& handles = doc_.state().handles();
  ImGui::Text("Handles (%zu)", handles.size());
  ImGui::SameLine();
  if (ImGui::SmallButton("New handle")) {
    const bool movable = opt.mode != PaintMode::Immovable;
    if (opt.mode == PaintMode::Support || opt.mode == PaintMode::Boundary) opt.mode = PaintMode::Handle;
    attempt("new handle", [&] { doc_.new_handle(movable); });
  }
  help_marker("An empty handle of the paint mode's kind (movable unless 'immovable'); paint it next");
  int to_delete = -1;
  const float list_height = std::min(static_cast<float>(handles.size()) + 0.5f, 6.5f) * ImGui::GetFrameHeightWithSpacing();
  if (!handles.empty() && ImGui::BeginChild("##handles", ImVec2(0, list_height), true)) {
    for (const HandleState& h : handles) {
      ImGui::PushID(h.id);
      const std::string label = fmt::format("handle {}{}: {} vertices", h.id, h.movable ? "" : " (immovable)",
                                            doc_.state().handle_size(h.id));
      if (ImGui::Selectable(label.c_str(), h.id == doc_.active_handle(), 0,
                            ImVec2(ImGui::GetContentRegionAvail().x - 4.0f * ImGui::GetFontSize(), 0)))
        attempt("select handle", [&] { doc_.set_active_handle(h.id); });
      ImGui::SameLine();
      if (ImGui::SmallButton("delete")) to_delete = h.id;
      ImGui::PopID();
    }
  }
  if (!handles.empty()) ImGui::EndChild();
  if (to_delete >= 0) attempt("delete handle", [&] { doc_.delete_handle(to_delete); });
  if (doc_.has_mesh() && !doc_.regions_problem().empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.75f, 0.3f, 1.0f));
    ImGui::TextWrapped("%s", doc_.regions_problem().c_str());
    ImGui::PopStyleColor();
  }
  ImGui::EndDisabled();
}

void App::panel_parameters() {
  if (!ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::BeginDisabled(!doc_.has_mesh() || tools_.transforming());
  const EditParameters current = doc_.parameters();
  EditParameters p = current;
  ImGui::TextUnformatted("Stiffness k");
  ImGui::SameLine();
  ImGui::RadioButton("1 membrane", &p.settings.order, 1);
  ImGui::SameLine();
  ImGui::RadioButton("2 thin plate", &p.settings.order, 2);
  ImGui::SameLine();
  ImGui::RadioButton("3", &p.settings.order, 3);
  help_marker("k = 3: minimal curvature variation");
  // Smoothness sliders edit a copy while dragged; the document gets one step on release.
  bool slider_done = false;
  const float max_c = static_cast<float>(p.settings.order - 1);
  if (!ImGui::IsAnyItemActive()) param_edit_ = current;
  const Smoothness& edited = param_edit_.settings.smoothness;
  float outer = static_cast<float>(edited.outer), inner = static_cast<float>(edited.inner);
  ImGui::BeginDisabled(p.settings.order == 1);
  if (ImGui::SliderFloat("outer smoothness", &outer, 0.0f, max_c, "C%.2f")) param_edit_.settings.smoothness.outer = outer;
  slider_done |= ImGui::IsItemDeactivatedAfterEdit();
  help_marker("Continuity across the support's outer boundary: 0 = crease (C0) ... k-1 = smooth");
  if (ImGui::SliderFloat("inner smoothness", &inner, 0.0f, max_c, "C%.2f")) param_edit_.settings.smoothness.inner = inner;
  slider_done |= ImGui::IsItemDeactivatedAfterEdit();
  help_marker("Continuity across the handle boundaries: 0 = crease (C0) ... k-1 = smooth");
  ImGui::EndDisabled();
  panel_segments();
  ImGui::Checkbox("anisotropic", &p.settings.anisotropic);
  help_marker("Bending that follows the support's shape (docs/anisotropic.md)");
  ImGui::SameLine();
  ImGui::Checkbox("multiresolution", &p.multiresolution);
  help_marker("Keep the surface detail while the base deforms (docs/multires.md)");
  bool nonlinear = p.deformation == Deformation::Nonlinear;
  if (ImGui::Checkbox("nonlinear", &nonlinear)) p.deformation = nonlinear ? Deformation::Nonlinear : Deformation::Linear;
  help_marker("Rotation-aware: large twists and bends keep their volume (docs/nonlinear.md); iterates on a worker thread while the display follows the handle");
  ImGui::SameLine();
  ImGui::BeginDisabled(!nonlinear);
  ImGui::Checkbox("keep volume", &p.nonlinear.preserve_volume);
  help_marker("Nonlinear model: keep the enclosed volume of closed meshes (a twisted bar does not neck); off for pulls that should add volume");
  ImGui::EndDisabled();
  if (slider_done) {
    p.settings.smoothness.outer = param_edit_.settings.smoothness.outer;
    p.settings.smoothness.inner = param_edit_.settings.smoothness.inner;
  }
  if (!(p == current)) attempt("parameters", [&] { doc_.set_parameters(p); });
  ImGui::EndDisabled();

  // The background precomputation.
  if (!doc_.has_mesh()) return;
  if (doc_.precompute_running()) {
    const std::string overlay = fmt::format("{} {:.0f}%", doc_.precompute_stage(), 100.0 * doc_.precompute_fraction());
    ImGui::ProgressBar(static_cast<float>(doc_.precompute_fraction()), ImVec2(-5.0f * ImGui::GetFontSize(), 0), overlay.c_str());
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) doc_.cancel_precompute();
  } else {
    const JobStatus st = doc_.precompute_status();
    ImGui::AlignTextToFramePadding();  // the same height as the progress bar: no jump
    if (st.state == JobState::Failed) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
      ImGui::TextWrapped("precomputation failed: %s", st.error.c_str());
      ImGui::PopStyleColor();
    } else if (st.state == JobState::Cancelled) {
      ImGui::TextUnformatted("precomputation cancelled");
      ImGui::SameLine();
      if (ImGui::SmallButton("Recompute")) attempt("recompute", [&] { doc_.recompute(); });
    } else if (doc_.solver_current() && doc_.solver()) {
      const PreparedSolver& ready = *doc_.solver();
      ImGui::TextDisabled("solver ready%s", !ready.multiresolution() ? ""
                                            : ready.detail_by_model() ? " (detail: model)"
                                                                      : " (multiresolution)");
      // Folds and flattened detail, so a problem shows without rendering a close-up; not during
      // a drag (O(support) per check), the last count stays.
      if (!tools_.transforming()) shown_problems_ = doc_.display_problems();
      if (shown_problems_) problems_line(*shown_problems_);
      // The precompute's warnings (an inaccurate solve, degenerate triangles, the anisotropic
      // fallback...); the frame's folds and flattened detail are in the problems line above.
      for (const std::string& w : edit_warnings(doc_.solver()->solver())) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.65f, 0.3f, 1.0f));
        ImGui::TextWrapped("%s", w.c_str());
        ImGui::PopStyleColor();
      }
      if (doc_.solver()->solver().stats().deformation == Deformation::Nonlinear) {
        // Its own wrapped line: the panel is narrower than the status with its suffix.
        const FrameTimings& f = doc_.last_timings();
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("nonlinear: %d iterations, residual %.1e%s", f.iterations, f.residual,
                           f.predicted ? " (predicted, refining)" : f.converged ? "" : " (refining)");
        ImGui::PopStyleColor();
      }
    }
  }
}

void App::panel_segments() {
  const EditParameters& current = doc_.parameters();
  if (current.settings.order == 1) return;  // a membrane is always C0
  ImGui::Text("Boundary segments (%zu)", current.settings.smoothness.segments.size());
  ImGui::SameLine();
  if (ImGui::SmallButton("New segment")) {
    tools_.options.mode = PaintMode::Boundary;
    attempt("new segment", [&] { doc_.set_active_segment(-1); });
  }
  help_marker("Paint a stretch of the coloured band next: it gets its own smoothness (starts at C0, a crease)");
  if (tools_.options.mode == PaintMode::Boundary || !current.settings.smoothness.segments.empty()) {  // the legend of the band colours
    ImDrawList* dl = ImGui::GetWindowDrawList();
    const ImVec2 at = ImGui::GetCursorScreenPos();
    const float w = 8.0f * ImGui::GetFontSize(), h = 0.6f * ImGui::GetFontSize();
    const int top = current.settings.order - 1;
    for (int i = 0; i < 64; ++i) {
      const viewer::Rgb c = viewer::smoothness_color(top * (i + 0.5) / 64.0);
      dl->AddRectFilled(ImVec2(at.x + w * i / 64.0f, at.y), ImVec2(at.x + w * (i + 1) / 64.0f + 0.5f, at.y + h),
                        ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], 1.0f)));
    }
    ImGui::Dummy(ImVec2(w, h));
    ImGui::SameLine();
    ImGui::TextDisabled(top == 1 ? "C0 .. C1 (band colour)" : "C0 .. C1 .. C2 (band colour)");
  }
  int to_delete = -1, committed = -1;
  const float max_c = static_cast<float>(current.settings.order - 1);
  for (std::size_t i = 0; i < current.settings.smoothness.segments.size() && i < param_edit_.settings.smoothness.segments.size(); ++i) {
    ImGui::PushID(static_cast<int>(i));
    const std::string label = fmt::format("{}: {} vertices", i, current.settings.smoothness.segments[i].vertices.size());
    if (ImGui::Selectable(label.c_str(), static_cast<int>(i) == doc_.active_segment(), 0, ImVec2(8.0f * ImGui::GetFontSize(), 0)))
      attempt("select segment", [&] { doc_.set_active_segment(static_cast<int>(i)); });
    ImGui::SameLine();
    ImGui::SetNextItemWidth(8.0f * ImGui::GetFontSize());
    float value = static_cast<float>(param_edit_.settings.smoothness.segments[i].value);
    if (ImGui::SliderFloat("##c", &value, 0.0f, max_c, "C%.2f")) param_edit_.settings.smoothness.segments[i].value = value;
    if (ImGui::IsItemDeactivatedAfterEdit()) committed = static_cast<int>(i);
    ImGui::SameLine();
    if (ImGui::SmallButton("delete")) to_delete = static_cast<int>(i);
    ImGui::PopID();
  }
  if (committed >= 0) {
    const double value = param_edit_.settings.smoothness.segments[static_cast<std::size_t>(committed)].value;
    attempt("segment smoothness", [&] { doc_.set_segment_value(committed, value); });
  }
  if (to_delete >= 0) attempt("delete segment", [&] { doc_.delete_segment(to_delete); });
}

void App::problems_line(const EditProblems& p) {
  ImGui::SameLine();
  if (p.ok()) {
    ImGui::TextDisabled("| no folds");
    return;
  }
  ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.65f, 0.3f, 1.0f));
  ImGui::Text("| %d folded edges", p.folded_edges);
  ImGui::PopStyleColor();
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("Edges whose dihedral angle grew by more than 60 degrees: %d\n"
                      "Vertices whose detail was flattened (bend tighter than the detail is tall): %d\n"
                      "Detail triangles flipped against their base: %d",
                      p.folded_edges, p.detail.overlaps, p.detail.flipped);
}

void App::panel_edit() {
  if (!ImGui::CollapsingHeader("Edit", ImGuiTreeNodeFlags_DefaultOpen)) return;
  ImGui::BeginDisabled(!doc_.has_mesh() || tools_.transforming());
  const std::string blocker = doc_.has_mesh() ? doc_.apply_blocker() : std::string("no mesh");
  ImGui::BeginDisabled(!blocker.empty());
  if (ImGui::Button("Apply")) attempt("apply", [&] { doc_.apply(); });
  ImGui::EndDisabled();
  if (ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
    ImGui::SetTooltip("%s", blocker.empty() ? "Bake the deformation into the mesh and start a new edit on it" : blocker.c_str());
  ImGui::SameLine();
  ImGui::BeginDisabled(!doc_.can_undo());
  if (ImGui::Button("Undo")) undo();
  ImGui::EndDisabled();
  if (doc_.can_undo() && ImGui::IsItemHovered()) ImGui::SetTooltip("Ctrl+Z: %s", doc_.history().next_undo()->label.c_str());
  ImGui::SameLine();
  ImGui::BeginDisabled(!doc_.can_redo());
  if (ImGui::Button("Redo")) redo();
  ImGui::EndDisabled();
  if (doc_.can_redo() && ImGui::IsItemHovered()) ImGui::SetTooltip("Ctrl+Shift+Z: %s", doc_.history().next_redo()->label.c_str());

  const std::filesystem::path base = doc_.path().empty() ? std::filesystem::path("edit") : std::filesystem::path(doc_.path());
  const auto beside = [&](const char* suffix) {
    return (base.parent_path() / (base.stem().string() + suffix)).string();
  };
  if (ImGui::Button("Export edit...")) prompt_export_edit();
  ImGui::SameLine();
  if (ImGui::Button("Import edit..."))
    ask_path("Import an edit file (replaces the current regions and handles)", "edit file (.json)", beside("-edit.json"),
             [this](const std::string& p) {
               if (attempt("cannot import the edit", [&] { doc_.import_edit(p); })) info("edit imported from " + p);
             });
  if (ImGui::Button("Save session..."))
    ask_path("Save the session (mesh path, applied edits, current edit)", "session file (.json)", beside("-session.json"),
             [this](const std::string& p) {
               if (attempt("cannot save the session", [&] { doc_.save_session(p); })) info("session saved to " + p);
             });
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(tools_.transforming());
  if (ImGui::Button("Load session..."))
    ask_path("Load a session (opens its mesh)", "session file (.json)", doc_.has_mesh() ? beside("-session.json") : std::string(),
             [this](const std::string& p) { load_session(p); });
  ImGui::EndDisabled();
}

void App::prompt_save_as() {
  if (!doc_.has_mesh()) return;
  ask_path("Save mesh as (the original file is never overwritten)", "mesh path (.obj .off .ply .stl .gltf .glb)",
           suggested_save_path(), [this](const std::string& p) { save_mesh(p); });
}

void App::prompt_export_edit() {
  if (!doc_.has_mesh()) return;
  const std::filesystem::path base = doc_.path().empty() ? std::filesystem::path("edit") : std::filesystem::path(doc_.path());
  ask_path("Export the edit (freeform deform MESH --edit FILE replays it)", "edit file (.json)",
           (base.parent_path() / (base.stem().string() + "-edit.json")).string(), [this](const std::string& p) {
             if (attempt("cannot export the edit", [&] { doc_.export_edit(p); })) info("edit written to " + p);
           });
}

}  // namespace freeform::editor
