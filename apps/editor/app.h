// The editor application: one GLFW window with an OpenGL 3.3 core context, Dear ImGui for the
// side panel / status line / overlays, and the GL-free editor state of src/editor/ (Document,
// ToolController, CameraController). Per frame: poll events, route them (ImGui widgets first,
// then the tool controller, then the camera), build the UI (so a change shows in the same
// frame), update the document's display and upload it, draw the mesh, the overlays and the UI.
// Sources: app.cpp (window, main loop, frame), documents.cpp (open / save / sessions, unsaved
// changes, messages), input.cpp (routing), panel.cpp (side panel), dialogs.cpp (status line,
// popups), overlay.cpp (screen-space drawing, region colours).
#pragma once

#include "frame_log.h"
#include "recent_files.h"

#include "editor/camera_controller.h"
#include "editor/document.h"
#include "editor/screen.h"
#include "editor/tool_controller.h"
#include "viewer/geometry_patch.h"
#include "viewer/render_scene.h"
#include "viewer/renderer.h"

#include <Eigen/Core>

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace freeform::editor {

struct AppOptions {
  std::string mesh;       // opened at start if not empty
  std::string session;    // loaded at start if not empty (after the mesh; its mesh wins)
  std::string frame_log;  // --frame-log FILE
  int width = 1280, height = 800;
};

// One window event, queued by the GLFW callbacks and routed after ImGui's NewFrame (so
// io.WantCaptureMouse/Keyboard describe the current frame).
struct InputEvent {
  enum class Kind { Button, Move, Scroll, Key, Char } kind = Kind::Move;
  int button = 0, action = 0, mods = 0, key = 0;
  unsigned codepoint = 0;
  Eigen::Vector2d pos = Eigen::Vector2d::Zero();  // window pixels (x right, y down)
  double scroll = 0;
};

// The view presets of the View section, in combo-box order.
inline constexpr const char* kViewPresetNames[] = {"front", "back", "left", "right", "top", "bottom", "iso"};
inline constexpr viewer::ViewPreset kViewPresets[] = {viewer::ViewPreset::Front, viewer::ViewPreset::Back,
                                                      viewer::ViewPreset::Left,  viewer::ViewPreset::Right,
                                                      viewer::ViewPreset::Top,   viewer::ViewPreset::Bottom,
                                                      viewer::ViewPreset::Iso};

// Who received a mouse press, and so gets its moves and the release.
enum class DragOwner { None, Tool, Orbit, Pan };

class App {
 public:
  explicit App(const AppOptions& options);  // throws freeform::Error if no window / GL 3.3
  ~App();
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  int run();  // until the window closes (after the unsaved-changes question)

 private:
  friend struct Callbacks;

  // app.cpp: the frame
  void frame();
  bool update_geometry(bool timed);  // true if positions were uploaded
  void fit_view();
  bool busy() const;  // something changes without input (drag, precompute, transform)

  // documents.cpp
  void open_mesh(const std::string& path);
  void load_session(const std::string& path);
  void after_new_document(const std::string& what);
  void save_mesh(const std::string& path, const std::function<void()>& then = {});
  void save_mesh_shortcut();  // Ctrl+S: the last save path, else ask
  void prompt_save_as();      // Ctrl+Shift+S
  void prompt_export_edit();  // Ctrl+E
  // 1 / 2 / 3 paint support / handle / immovable, B / L / O brush / lasso / flood (no modifier,
  // no transform running); true if used.
  bool tool_shortcut(int key);
  std::string suggested_save_path() const;
  void update_title();
  void request_quit();
  // Runs `action` now, or after the unsaved-changes popup (Save / Discard; Cancel drops it).
  void unless_unsaved(const std::string& what, std::function<void()> action);
  void error(const std::string& message);  // popup + message line
  void info(const std::string& message);   // message line
  // Runs a document command; an exception becomes an error popup prefixed by `what`.
  bool attempt(const std::string& what, const std::function<void()>& command);
  void remember_recent(const std::string& path);

  // input.cpp
  void route_events();
  void on_button(const InputEvent& e);
  void on_move(const InputEvent& e);
  void on_scroll(const InputEvent& e);
  void on_key(const InputEvent& e);
  void on_char(const InputEvent& e);
  bool global_shortcut(const InputEvent& e);  // Ctrl+Z/Shift+Z/S/Q, F; true if consumed
  void undo();
  void redo();
  Eigen::Vector2d to_viewport(const Eigen::Vector2d& window_px) const;
  bool in_viewport(const Eigen::Vector2d& window_px) const;

  // panel.cpp
  void build_ui();
  void panel_file();
  void panel_view();
  void panel_regions();
  void panel_parameters();
  void panel_edit();
  void problems_line(const EditProblems& p);

  // dialogs.cpp
  void status_line();
  void popups();

  // overlay.cpp
  void draw_overlays();
  void recolor();  // region colours of the current edit (support blue, handles green, ...)
  // Colour the smoothness band by c: while painting segments or when there are some.
  bool band_shown() const;
  void panel_segments();  // boundary smoothness segments: list, value sliders, legend

  // Screen layout in window pixels: the panel on the left, the status line at the bottom,
  // the 3D viewport in the rest.
  struct Layout {
    float panel_width = 340, status_height = 48;
    int x = 0, y = 0, width = 1, height = 1;  // viewport
  };
  void update_layout();
  ScreenView screen_view() const { return {camera_.camera(), layout_.width, layout_.height}; }
  double aspect() const { return static_cast<double>(layout_.width) / layout_.height; }

  AppOptions options_;
  GLFWwindow* window_ = nullptr;
  bool imgui_ready_ = false;
  std::string title_;
  std::unique_ptr<viewer::Renderer> renderer_;
  CameraController camera_;
  viewer::DrawOptions draw_;
  Layout layout_;
  int up_axis_ = 0;      // 0: z up, 1: y up (the turntable axis and the presets)
  int view_preset_ = 0;  // index into the panel's preset list
  bool fit_pending_ = false;

  // The document and its tools (the tools hold a reference to doc_: declared after it).
  Document doc_;
  ToolController tools_{doc_};
  viewer::RenderScene scene_;
  viewer::GeometryPatch patch_;  // what a frame can change between display resets
  std::optional<EditProblems> shown_problems_;
  bool scene_uploaded_ = false;
  std::uint64_t shown_display_version_ = 0, shown_region_version_ = 0, shown_reset_version_ = 0;
  int shown_active_handle_ = -2;
  bool shown_band_ = false;  // the smoothness band is coloured by c
  int shown_active_segment_ = -2;
  std::string save_path_;  // where Ctrl+S writes (set by Save as)
  std::string shown_background_error_;
  EditParameters param_edit_;  // the parameters while a slider is dragged

  // Input.
  std::vector<InputEvent> events_;
  Eigen::Vector2d event_cursor_ = Eigen::Vector2d::Zero();  // position of the last queued move
  std::vector<std::string> dropped_;
  struct DeferredKey {
    int key, scancode, mods;
  };
  std::vector<int> keys_pressed_this_frame_;  // since the last frame: their release waits a frame
  std::vector<DeferredKey> deferred_releases_;
  DragOwner drag_ = DragOwner::None;
  int drag_button_ = -1;
  Eigen::Vector2d last_mouse_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d mouse_ = Eigen::Vector2d::Zero();  // window pixels
  bool mouse_in_view_ = false;
  int mods_ = 0;  // GLFW modifier bits of the last event

  // dialogs.cpp: a "Save as..." style popup (a path field and OK / Cancel; OK runs the action).
  struct PathPrompt {
    std::string title, label, path;
    std::function<void(const std::string&)> action;
    bool open_next_frame = false;
  } prompt_;
  void ask_path(const std::string& title, const std::string& label, const std::string& initial,
                std::function<void(const std::string&)> action);

  // Panel state.
  std::string path_field_;
  RecentFiles recent_;
  std::string message_;
  bool message_is_error_ = false;
  std::vector<std::string> pending_errors_;  // shown one popup at a time
  struct Confirm {
    bool open = false;
    std::string what;  // "quitting", "opening FILE", ...
    std::function<void()> action;
  } confirm_;
  bool quit_confirmed_ = false;

  // Timings of the last frame (ms).
  struct Timings {
    double evaluate = 0, detail = 0, normals = 0, upload = 0, draw = 0, ui = 0, frame = 0;
  } timings_;
  Timings status_timings_;  // the status line keeps the last evaluation's numbers
  FrameLog frame_log_;
  long frame_index_ = 0;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  int redraw_frames_ = 3;  // frames still to draw before waiting for events
};

}  // namespace freeform::editor
