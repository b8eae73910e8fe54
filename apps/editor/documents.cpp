// The document's life cycle in the window: open / load (asking first when there are unsaved
// changes), save, the recent files, the title, and how errors and messages reach the user.
#include "app.h"

#include <GLFW/glfw3.h>

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>

namespace freeform::editor {

bool App::attempt(const std::string& what, const std::function<void()>& command) {
  try {
    command();
    update_title();
    return true;
  } catch (const std::exception& e) {
    error(what + ": " + e.what());
    update_title();
    return false;
  }
}

void App::remember_recent(const std::string& path) {
  recent_.add(path);
  try {
    recent_.save();
  } catch (const std::exception& e) {
    info(std::string("the recent files list was not saved: ") + e.what());
  }
}

void App::after_new_document(const std::string& what) {
  tools_.reset();
  scene_uploaded_ = false;
  save_path_.clear();
  fit_pending_ = true;  // after the next frame's layout and upload
  param_edit_ = doc_.parameters();
  shown_background_error_.clear();
  remember_recent(doc_.path());
  path_field_ = doc_.path();
  std::string note = fmt::format("{}: {} vertices, {} triangles", what, doc_.rest_mesh().n_vertices(), doc_.rest_mesh().n_faces());
  for (const auto& w : doc_.warnings()) note += "; " + w;
  info(note);
  update_title();
}

void App::open_mesh(const std::string& path) {
  if (path.empty()) return error("Open: type a mesh path into the field first");
  unless_unsaved("opening " + path, [this, path] {
    // Document::open's errors name the file (the readers' and the manifold check's).
    if (attempt("cannot open the mesh", [&] { doc_.open(path); })) after_new_document("opened " + path);
  });
}

void App::load_session(const std::string& path) {
  if (path.empty()) return error("Load session: type the session file path first");
  unless_unsaved("loading " + path, [this, path] {
    if (attempt("cannot load the session " + path, [&] { doc_.load_session(path); }))
      after_new_document("session " + path + " loaded, mesh " + doc_.path());
  });
}

void App::unless_unsaved(const std::string& what, std::function<void()> action) {
  if (doc_.has_mesh() && doc_.dirty()) {
    confirm_ = {true, what, std::move(action)};  // popups() asks Save / Discard / Cancel
    redraw_frames_ = std::max(redraw_frames_, 3);
  } else {
    action();
  }
}

void App::save_mesh(const std::string& path, const std::function<void()>& then) {
  if (!doc_.has_mesh()) return error("Save: no mesh is open");
  if (path.empty()) return error("Save as: type the output path into the field first");
  std::vector<std::string> dropped;
  if (attempt("cannot save the mesh", [&] { dropped = doc_.save_mesh(path); })) {
    save_path_ = path;
    info(dropped.empty() ? "saved " + path : "saved " + path + " without the input's " + dropped.front() +
                                                  (dropped.size() > 1 ? fmt::format(" and {} more", dropped.size() - 1) : ""));
    if (then) then();
  }
}

std::string App::suggested_save_path() const {
  if (!save_path_.empty()) return save_path_;
  const std::filesystem::path p(doc_.path());
  if (p.empty()) return "edited.off";
  return (p.parent_path() / (p.stem().string() + "-edited" + p.extension().string())).string();
}

void App::save_mesh_shortcut() {
  if (!doc_.has_mesh()) return error("Save: no mesh is open");
  if (!save_path_.empty()) return save_mesh(save_path_);
  ask_path("Save mesh as (the original file is never overwritten)", "mesh path (.obj .off .ply .stl .gltf .glb)",
           suggested_save_path(), [this](const std::string& p) { save_mesh(p); });
}

void App::update_title() {
  std::string title = "Freeform editor";
  if (doc_.has_mesh()) {
    const std::string name = doc_.path().empty() ? std::string("untitled") : std::filesystem::path(doc_.path()).filename().string();
    title = name + (doc_.dirty() ? " *" : "") + " - " + title;
  }
  if (title == title_) return;  // a title change is a round trip to the window system
  title_ = title;
  glfwSetWindowTitle(window_, title.c_str());
}

void App::request_quit() {
  unless_unsaved("quitting", [this] { quit_confirmed_ = true; });
}

void App::error(const std::string& message) {
  message_ = message;
  message_is_error_ = true;
  pending_errors_.push_back(message);
  redraw_frames_ = std::max(redraw_frames_, 3);
}

void App::info(const std::string& message) {
  message_ = message;
  message_is_error_ = false;
}

}  // namespace freeform::editor
