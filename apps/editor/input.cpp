// Input routing: ImGui widgets first (io.WantCaptureMouse / WantCaptureKeyboard), then the
// tool controller, then the camera. A press decides who owns the drag; that owner gets the
// moves and the release even when the cursor leaves the viewport.
#include "app.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <optional>

namespace freeform::editor {
namespace {

Modifiers modifiers(int mods) {
  return {(mods & GLFW_MOD_SHIFT) != 0, (mods & GLFW_MOD_CONTROL) != 0, (mods & GLFW_MOD_ALT) != 0};
}

std::optional<MouseButton> mouse_button(int button) {
  switch (button) {
    case GLFW_MOUSE_BUTTON_LEFT: return MouseButton::Left;
    case GLFW_MOUSE_BUTTON_MIDDLE: return MouseButton::Middle;
    case GLFW_MOUSE_BUTTON_RIGHT: return MouseButton::Right;
    default: return std::nullopt;
  }
}

std::optional<Key> tool_key(int key) {
  switch (key) {
    case GLFW_KEY_G: return Key::G;
    case GLFW_KEY_R: return Key::R;
    case GLFW_KEY_S: return Key::S;
    case GLFW_KEY_X: return Key::X;
    case GLFW_KEY_Y: return Key::Y;
    case GLFW_KEY_Z: return Key::Z;
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER: return Key::Enter;
    case GLFW_KEY_ESCAPE: return Key::Escape;
    case GLFW_KEY_BACKSPACE: return Key::Backspace;
    case GLFW_KEY_LEFT_BRACKET: return Key::BracketLeft;
    case GLFW_KEY_RIGHT_BRACKET: return Key::BracketRight;
    default: return std::nullopt;
  }
}

}  // namespace

Eigen::Vector2d App::to_viewport(const Eigen::Vector2d& p) const { return p - Eigen::Vector2d(layout_.x, layout_.y); }

bool App::in_viewport(const Eigen::Vector2d& p) const {
  const Eigen::Vector2d v = to_viewport(p);
  return v.x() >= 0 && v.y() >= 0 && v.x() < layout_.width && v.y() < layout_.height;
}

void App::route_events() {
  std::vector<InputEvent> events;
  events.swap(events_);
  for (const InputEvent& e : events) {
    try {
      switch (e.kind) {
        case InputEvent::Kind::Button: on_button(e); break;
        case InputEvent::Kind::Move: on_move(e); break;
        case InputEvent::Kind::Scroll: on_scroll(e); break;
        case InputEvent::Kind::Key: on_key(e); break;
        case InputEvent::Kind::Char: on_char(e); break;
      }
    } catch (const std::exception& ex) {  // a tool refused (e.g. a singular scale): say so, keep going
      error(ex.what());
    }
  }
  update_title();
}

void App::on_button(const InputEvent& e) {
  const ImGuiIO& io = ImGui::GetIO();
  mouse_ = e.pos;
  mods_ = e.mods;
  const std::optional<MouseButton> button = mouse_button(e.button);
  if (e.action == GLFW_RELEASE) {
    if (e.button != drag_button_) return;
    if (drag_ == DragOwner::Tool && button) tools_.mouse_up(*button, to_viewport(e.pos));
    drag_ = DragOwner::None;
    drag_button_ = -1;
    return;
  }
  if (drag_ != DragOwner::None || !button) return;  // one drag at a time
  // A running G / R / S transform takes clicks anywhere (confirm / cancel); otherwise the
  // widgets keep their clicks and only the viewport's go further.
  const bool over_ui = io.WantCaptureMouse || !in_viewport(e.pos);
  if (over_ui && !tools_.transforming()) return;
  last_mouse_ = e.pos;
  drag_button_ = e.button;
  if (doc_.has_mesh() && tools_.mouse_down(*button, to_viewport(e.pos), modifiers(e.mods))) {
    drag_ = DragOwner::Tool;
    return;
  }
  if (over_ui) {
    drag_button_ = -1;
    return;
  }
  // The camera: middle orbits (Shift: pans); left orbits (Shift: pans) and right pans when no
  // tool took them.
  if (*button == MouseButton::Right) {
    drag_ = DragOwner::Pan;
  } else {
    drag_ = (e.mods & GLFW_MOD_SHIFT) ? DragOwner::Pan : DragOwner::Orbit;
  }
}

void App::on_move(const InputEvent& e) {
  mouse_ = e.pos;
  mouse_in_view_ = in_viewport(e.pos) && !ImGui::GetIO().WantCaptureMouse;
  const Eigen::Vector2d d = e.pos - last_mouse_;
  last_mouse_ = e.pos;
  switch (drag_) {
    case DragOwner::Orbit: camera_.orbit(d.x(), d.y()); break;
    case DragOwner::Pan: camera_.pan(d.x(), d.y(), layout_.height); break;
    case DragOwner::Tool: tools_.mouse_move(to_viewport(e.pos)); break;
    case DragOwner::None:
      if (doc_.has_mesh() && (mouse_in_view_ || tools_.transforming())) tools_.mouse_move(to_viewport(e.pos));
      break;
  }
}

void App::on_scroll(const InputEvent& e) {
  if (ImGui::GetIO().WantCaptureMouse || !in_viewport(e.pos)) return;
  int mods = 0;
  if (glfwGetKey(window_, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS)
    mods |= GLFW_MOD_SHIFT;
  if (glfwGetKey(window_, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS)
    mods |= GLFW_MOD_CONTROL;
  if (glfwGetKey(window_, GLFW_KEY_LEFT_ALT) == GLFW_PRESS || glfwGetKey(window_, GLFW_KEY_RIGHT_ALT) == GLFW_PRESS)
    mods |= GLFW_MOD_ALT;
  if (doc_.has_mesh() && tools_.scroll(e.scroll, modifiers(mods))) return;
  camera_.wheel(e.scroll);
}

void App::on_key(const InputEvent& e) {
  mods_ = e.mods;
  if (ImGui::GetIO().WantCaptureKeyboard) return;  // typing into a field, or a popup is open
  if (e.action == GLFW_RELEASE) return;
  if (global_shortcut(e)) return;
  if ((e.mods & (GLFW_MOD_CONTROL | GLFW_MOD_ALT | GLFW_MOD_SUPER)) != 0 && e.key != GLFW_KEY_LEFT_BRACKET &&
      e.key != GLFW_KEY_RIGHT_BRACKET)
    return;  // unknown shortcut: not a tool key
  if (e.mods == 0 && tool_shortcut(e.key)) return;
  if (const auto key = tool_key(e.key); key && doc_.has_mesh()) tools_.key(*key, modifiers(e.mods));
}

bool App::tool_shortcut(int key) {
  if (tools_.transforming() || tools_.stroking()) return false;
  switch (key) {
    case GLFW_KEY_1: tools_.options.mode = PaintMode::Support; return true;
    case GLFW_KEY_2: tools_.options.mode = PaintMode::Handle; return true;
    case GLFW_KEY_3: tools_.options.mode = PaintMode::Immovable; return true;
    case GLFW_KEY_4: tools_.options.mode = PaintMode::Boundary; return true;
    case GLFW_KEY_B: tools_.options.tool = Tool::Brush; return true;
    case GLFW_KEY_L: tools_.options.tool = Tool::Lasso; return true;
    case GLFW_KEY_O: tools_.options.tool = Tool::Flood; return true;
    default: return false;
  }
}

void App::on_char(const InputEvent& e) {
  if (ImGui::GetIO().WantCaptureKeyboard || !doc_.has_mesh()) return;
  const unsigned c = e.codepoint;
  if ((c >= '0' && c <= '9') || c == '.' || c == '-') tools_.character(static_cast<char>(c));
}

bool App::global_shortcut(const InputEvent& e) {
  const bool ctrl = (e.mods & GLFW_MOD_CONTROL) != 0, shift = (e.mods & GLFW_MOD_SHIFT) != 0;
  if (e.action != GLFW_PRESS) return false;
  if (ctrl && e.key == GLFW_KEY_Q) {
    request_quit();
    return true;
  }
  if (ctrl && e.key == GLFW_KEY_S) {
    shift ? prompt_save_as() : save_mesh_shortcut();
    return true;
  }
  if (ctrl && e.key == GLFW_KEY_E) {
    prompt_export_edit();
    return true;
  }
  if (ctrl && e.key == GLFW_KEY_Z) {
    shift ? redo() : undo();
    return true;
  }
  if (ctrl && e.key == GLFW_KEY_Y) {
    redo();
    return true;
  }
  if (!ctrl && !shift && e.key == GLFW_KEY_F && !tools_.transforming()) {
    if (doc_.has_mesh()) camera_.fit(scene_.bounds, aspect());
    return true;
  }
  return false;
}

void App::undo() {
  if (tools_.transforming() || tools_.stroking()) return info("finish the current transform or stroke first");
  if (!doc_.can_undo()) return info("nothing to undo");
  const std::string label = doc_.history().next_undo()->label;
  if (attempt("undo failed", [&] { doc_.undo(); })) info("undone: " + label);
}

void App::redo() {
  if (tools_.transforming() || tools_.stroking()) return info("finish the current transform or stroke first");
  if (!doc_.can_redo()) return info("nothing to redo");
  const std::string label = doc_.history().next_redo()->label;
  if (attempt("redo failed", [&] { doc_.redo(); })) info("redone: " + label);
}

}  // namespace freeform::editor
