// The status line (counts, timings, messages) and the modal popups: errors, unsaved changes
// (Save / Discard / Cancel), and the path prompts that stand in for file dialogs.
#include "app.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <fmt/core.h>

#include <filesystem>

namespace freeform::editor {
namespace {

constexpr ImGuiWindowFlags kFixed = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                                    ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus;
constexpr float kStatusPadding = 4.0f;

// A key pressed inside a popup, ignoring the frame it appeared in (the key that opened it).
bool key_pressed(ImGuiKey key) { return !ImGui::IsWindowAppearing() && ImGui::IsKeyPressed(ImGui::GetKeyIndex(key), false); }

}  // namespace

void App::ask_path(const std::string& title, const std::string& label, const std::string& initial,
                   std::function<void(const std::string&)> action) {
  prompt_.title = title;
  prompt_.label = label;
  prompt_.path = initial;
  prompt_.action = std::move(action);
  prompt_.open_next_frame = true;
}

void App::status_line() {
  int w = 0, h = 0;
  glfwGetWindowSize(window_, &w, &h);
  ImGui::SetNextWindowPos(ImVec2(0, static_cast<float>(h) - layout_.status_height));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(w), layout_.status_height));
  ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(8, kStatusPadding));
  if (ImGui::Begin("##status", nullptr, kFixed | ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoScrollbar)) {
    std::string counts;
    if (!doc_.has_mesh()) {
      counts = "no mesh: type a path, drop a file or pick a recent one";
    } else {
      const EditState& st = doc_.state();
      counts = fmt::format("{} vertices | support {}  free {}", doc_.rest_mesh().n_vertices(), st.n_support(), st.n_free());
      for (const HandleState& hs : st.handles())
        counts += fmt::format("  {}{}: {}", hs.movable ? "handle " : "immovable ", hs.id, st.handle_size(hs.id));
    }
    ImGui::TextUnformatted(counts.c_str());
    const Timings& t = status_timings_;
    const std::string times = fmt::format("evaluate {:.2f} ms  detail {:.2f} ms  upload {:.2f} ms  draw {:.1f} ms",
                                          t.evaluate, t.detail, t.upload, t.draw);
    const float tw = ImGui::CalcTextSize(times.c_str()).x;
    ImGui::SameLine(std::max(ImGui::GetCursorPosX() + 20.0f, static_cast<float>(w) - tw - 10.0f));
    ImGui::TextUnformatted(times.c_str());
    const std::string transform = tools_.transform_status();
    if (!transform.empty()) {
      ImGui::TextColored(ImVec4(1.0f, 0.85f, 0.3f, 1.0f), "%s", transform.c_str());
    } else if (message_is_error_) {
      ImGui::TextColored(ImVec4(1.0f, 0.45f, 0.4f, 1.0f), "%s", message_.c_str());
    } else {
      ImGui::TextUnformatted(message_.c_str());
    }
  }
  ImGui::End();
  ImGui::PopStyleVar();
}

void App::popups() {
  // Modal popups open centred on the viewport.
  const ImVec2 centre(static_cast<float>(layout_.x) + 0.5f * layout_.width, static_cast<float>(layout_.y) + 0.5f * layout_.height);
  const auto centred = [&] { ImGui::SetNextWindowPos(centre, ImGuiCond_Appearing, ImVec2(0.5f, 0.5f)); };
  // Errors: one modal at a time, oldest first.
  if (!pending_errors_.empty() && !ImGui::IsPopupOpen("Error")) ImGui::OpenPopup("Error");
  centred();
  if (ImGui::BeginPopupModal("Error", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::PushTextWrapPos(32.0f * ImGui::GetFontSize());
    ImGui::TextUnformatted(pending_errors_.empty() ? "" : pending_errors_.front().c_str());
    ImGui::PopTextWrapPos();
    if (ImGui::Button("OK", ImVec2(6.0f * ImGui::GetFontSize(), 0)) || key_pressed(ImGuiKey_Enter)) {
      if (!pending_errors_.empty()) pending_errors_.erase(pending_errors_.begin());
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }

  if (confirm_.open && !ImGui::IsPopupOpen("Unsaved changes")) ImGui::OpenPopup("Unsaved changes");
  centred();
  if (ImGui::BeginPopupModal("Unsaved changes", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    const std::string name = doc_.path().empty() ? std::string("The mesh") : std::filesystem::path(doc_.path()).filename().string();
    ImGui::Text("%s has unsaved changes.", name.c_str());
    ImGui::Text("Save the mesh before %s?", confirm_.what.c_str());
    const ImVec2 size(6.0f * ImGui::GetFontSize(), 0);
    if (ImGui::Button("Save", size)) {
      ImGui::CloseCurrentPopup();
      // Go on once saved; a failed save keeps everything as it is (the error shows).
      const auto go_on = [this, action = confirm_.action] {
        if (!doc_.dirty() && action) action();
      };
      confirm_.open = false;
      if (!save_path_.empty()) {
        save_mesh(save_path_, go_on);
      } else {
        ask_path("Save mesh as, then go on", "mesh path (.obj .off .ply .stl .gltf .glb)", suggested_save_path(),
                 [this, go_on](const std::string& p) { save_mesh(p, go_on); });
      }
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard", size)) {
      ImGui::CloseCurrentPopup();
      confirm_.open = false;
      const auto action = std::move(confirm_.action);
      if (action) action();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel", size) || key_pressed(ImGuiKey_Escape)) {
      ImGui::CloseCurrentPopup();
      confirm_ = {};
    }
    ImGui::EndPopup();
  }

  if (prompt_.open_next_frame) {
    ImGui::OpenPopup("##path prompt");
    prompt_.open_next_frame = false;
  }
  centred();
  if (ImGui::BeginPopupModal("##path prompt", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted(prompt_.title.c_str());
    if (ImGui::IsWindowAppearing()) ImGui::SetKeyboardFocusHere();
    ImGui::SetNextItemWidth(28.0f * ImGui::GetFontSize());
    bool ok = ImGui::InputTextWithHint("##prompt path", prompt_.label.c_str(), &prompt_.path,
                                       ImGuiInputTextFlags_EnterReturnsTrue | ImGuiInputTextFlags_AutoSelectAll);
    const ImVec2 size(6.0f * ImGui::GetFontSize(), 0);
    ok |= ImGui::Button("OK", size);
    ImGui::SameLine();
    if (ImGui::Button("Cancel", size) || key_pressed(ImGuiKey_Escape)) {
      ImGui::CloseCurrentPopup();
    } else if (ok) {
      ImGui::CloseCurrentPopup();
      const auto action = prompt_.action;  // may open another prompt
      if (action) action(prompt_.path);
    }
    ImGui::EndPopup();
  }
}

}  // namespace freeform::editor
