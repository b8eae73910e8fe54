#include "app.h"

#include "viewer/gl_util.h"
#include "viewer/region_colors.h"

#include "freeform/io/mesh_io.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>

#include <fmt/core.h>

#include <algorithm>
#include <csignal>
#include <filesystem>

namespace freeform::editor {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::string g_glfw_error;  // the last GLFW error, for the exception when there is no window
// SIGINT / SIGTERM: leave the main loop without the unsaved-changes question (the frame log is
// still written). Checked at least every half second.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void on_stop_signal(int) { g_stop_signal = 1; }

}  // namespace

// GLFW callbacks: forward to ImGui's backend, then queue the event for route_events().
// ImGui 1.86 samples key states once per frame, so a key pressed and released between two
// frames (fast typists, xdotool) would be lost: such a release reaches ImGui a frame later.
struct Callbacks {
  static App& app(GLFWwindow* w) { return *static_cast<App*>(glfwGetWindowUserPointer(w)); }
  // The pointer position in event order (glfwGetCursorPos would ask the window system for
  // the position now, after later moves of the same batch).
  static Eigen::Vector2d cursor(GLFWwindow* w) { return app(w).event_cursor_; }
  static void button(GLFWwindow* w, int button, int action, int mods) {
    ImGui_ImplGlfw_MouseButtonCallback(w, button, action, mods);
    InputEvent e;
    e.kind = InputEvent::Kind::Button;
    e.button = button, e.action = action, e.mods = mods, e.pos = cursor(w);
    app(w).events_.push_back(e);
  }
  static void move(GLFWwindow* w, double x, double y) {
    app(w).event_cursor_ = {x, y};
    InputEvent e;
    e.kind = InputEvent::Kind::Move;
    e.pos = {x, y};
    app(w).events_.push_back(e);
  }
  static void scroll(GLFWwindow* w, double dx, double dy) {
    ImGui_ImplGlfw_ScrollCallback(w, dx, dy);
    InputEvent e;
    e.kind = InputEvent::Kind::Scroll;
    e.scroll = dy, e.pos = cursor(w);
    app(w).events_.push_back(e);
  }
  static void key(GLFWwindow* w, int key, int scancode, int action, int mods) {
    App& a = app(w);
    auto& pressed = a.keys_pressed_this_frame_;
    if (action == GLFW_RELEASE && std::find(pressed.begin(), pressed.end(), key) != pressed.end()) {
      a.deferred_releases_.push_back({key, scancode, mods});
    } else {
      if (action == GLFW_PRESS) pressed.push_back(key);
      ImGui_ImplGlfw_KeyCallback(w, key, scancode, action, mods);
    }
    InputEvent e;
    e.kind = InputEvent::Kind::Key;
    e.key = key, e.action = action, e.mods = mods, e.pos = cursor(w);
    a.events_.push_back(e);
  }
  static void character(GLFWwindow* w, unsigned codepoint) {
    ImGui_ImplGlfw_CharCallback(w, codepoint);
    InputEvent e;
    e.kind = InputEvent::Kind::Char;
    e.codepoint = codepoint, e.pos = cursor(w);
    app(w).events_.push_back(e);
  }
  static void focus(GLFWwindow* w, int focused) { ImGui_ImplGlfw_WindowFocusCallback(w, focused); }
  static void enter(GLFWwindow* w, int entered) { ImGui_ImplGlfw_CursorEnterCallback(w, entered); }
  static void drop(GLFWwindow* w, int count, const char** paths) {
    if (count > 0) app(w).dropped_.emplace_back(paths[0]);  // opened in the next frame
  }
  static void close(GLFWwindow* w) {
    glfwSetWindowShouldClose(w, GLFW_FALSE);  // answered by the unsaved-changes popup
    app(w).request_quit();
  }
  static void refresh(GLFWwindow* w) { app(w).redraw_frames_ = std::max(app(w).redraw_frames_, 2); }
};

App::App(const AppOptions& options) : options_(options), frame_log_(options.frame_log) {
  glfwSetErrorCallback([](int code, const char* text) { g_glfw_error = fmt::format("GLFW error {:#x}: {}", code, text); });
  if (!glfwInit()) throw viewer::RenderError("cannot initialise GLFW (no display? set DISPLAY): " + g_glfw_error);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, 4);
  window_ = glfwCreateWindow(options.width, options.height, "Freeform editor", nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw viewer::RenderError("cannot create a window with an OpenGL 3.3 core context: " + g_glfw_error);
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(1);
  glfwSetWindowUserPointer(window_, this);
  glfwGetCursorPos(window_, &event_cursor_.x(), &event_cursor_.y());
  glfwSetMouseButtonCallback(window_, Callbacks::button);
  glfwSetCursorPosCallback(window_, Callbacks::move);
  glfwSetScrollCallback(window_, Callbacks::scroll);
  glfwSetKeyCallback(window_, Callbacks::key);
  glfwSetCharCallback(window_, Callbacks::character);
  glfwSetWindowFocusCallback(window_, Callbacks::focus);
  glfwSetCursorEnterCallback(window_, Callbacks::enter);
  glfwSetDropCallback(window_, Callbacks::drop);
  glfwSetWindowCloseCallback(window_, Callbacks::close);
  glfwSetWindowRefreshCallback(window_, Callbacks::refresh);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;  // fixed layout: nothing to remember
  ImGui::StyleColorsDark();
  ImGui::GetStyle().WindowRounding = 0.0f;
  ImGui_ImplGlfw_InitForOpenGL(window_, false);  // our callbacks forward to the backend
  ImGui_ImplOpenGL3_Init("#version 330 core");
  imgui_ready_ = true;

  renderer_ = std::make_unique<viewer::Renderer>();
  draw_.background = {0.93f, 0.94f, 0.96f};
  recent_ = RecentFiles(RecentFiles::default_location());
  recent_.load();
  camera_.reset({Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1)}, viewer::ViewPreset::Front,
                viewer::UpAxis::Z, 1.0);
  param_edit_ = doc_.parameters();

  if (!options.mesh.empty()) {
    path_field_ = options.mesh;
    open_mesh(options.mesh);
  }
  if (!options.session.empty()) load_session(options.session);
  update_title();
}

App::~App() {
  renderer_.reset();  // needs the context
  if (imgui_ready_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

bool App::busy() const {
  return drag_ != DragOwner::None || doc_.precompute_running() || tools_.transforming() || tools_.stroking();
}

int App::run() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  while (!quit_confirmed_ && !g_stop_signal) {
    // Wait for input when nothing changes on its own.
    if (redraw_frames_ > 0 || busy()) {
      glfwPollEvents();
    } else if (doc_.refining()) {
      glfwWaitEventsTimeout(1.0 / 30.0);  // the nonlinear model's worker publishes new iterates
    } else {
      glfwWaitEventsTimeout(0.5);
    }
    redraw_frames_ = std::max(redraw_frames_ - 1, 0);
    if (!events_.empty() || !dropped_.empty()) redraw_frames_ = std::max(redraw_frames_, 3);  // ImGui settles over a few frames
    frame();
  }
  try {
    frame_log_.write();
    if (frame_log_.enabled()) fmt::print("frame log: {} frames written to {}\n", frame_log_.size(), options_.frame_log);
  } catch (const std::exception& e) {
    fmt::print(stderr, "freeform-editor: {}\n", e.what());
    return 1;
  }
  return 0;
}

void App::update_layout() {
  int w = 0, h = 0;
  glfwGetWindowSize(window_, &w, &h);
  const float font = ImGui::GetFontSize();
  layout_.panel_width = std::min(27.0f * font, 0.45f * static_cast<float>(w));
  layout_.status_height = 2.0f * ImGui::GetTextLineHeightWithSpacing() + 8.0f;  // two lines, padding 4
  layout_.x = static_cast<int>(layout_.panel_width);
  layout_.y = 0;
  layout_.width = std::max(w - layout_.x, 1);
  layout_.height = std::max(h - static_cast<int>(layout_.status_height), 1);
}

void App::frame() {
  const auto t_frame = Clock::now();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  update_layout();
  for (const std::string& path : std::exchange(dropped_, {})) {
    path_field_ = path;
    if (path.ends_with(".json")) {
      load_session(path);
    } else {
      open_mesh(path);
    }
  }
  tools_.set_view(screen_view());
  route_events();

  const auto t_ui = Clock::now();
  build_ui();
  double ui_ms = ms_since(t_ui);

  const bool geometry = update_geometry(frame_log_.enabled());
  if (fit_pending_ && doc_.has_mesh()) {
    fit_view();
    fit_pending_ = false;
  }
  tools_.set_view(screen_view());  // the camera may have moved: overlays match the drawn frame
  const auto t_overlay = Clock::now();
  draw_overlays();
  ui_ms += ms_since(t_overlay);

  int fb_w = 0, fb_h = 0, win_w = 1, win_h = 1;
  glfwGetFramebufferSize(window_, &fb_w, &fb_h);
  glfwGetWindowSize(window_, &win_w, &win_h);
  const double sx = static_cast<double>(fb_w) / std::max(win_w, 1), sy = static_cast<double>(fb_h) / std::max(win_h, 1);
  viewer::DrawOptions draw = draw_;
  draw.viewport_x = static_cast<int>(layout_.x * sx);
  draw.viewport_y = static_cast<int>(fb_h - (layout_.y + layout_.height) * sy);
  const int vw = std::max(static_cast<int>(layout_.width * sx), 1), vh = std::max(static_cast<int>(layout_.height * sy), 1);
  const auto t_draw = Clock::now();
  try {
    renderer_->draw(camera_.camera(), vw, vh, draw);
    if (frame_log_.enabled()) glFinish();
  } catch (const std::exception& e) {
    error(e.what());
  }
  timings_.draw = ms_since(t_draw);
  status_timings_.draw = timings_.draw;

  const auto t_render = Clock::now();
  ImGui::Render();
  glViewport(0, 0, fb_w, fb_h);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  ui_ms += ms_since(t_render);
  timings_.ui = ui_ms;
  // This frame saw the keys pressed before it: releases held back reach ImGui now.
  keys_pressed_this_frame_.clear();
  for (const DeferredKey& k : std::exchange(deferred_releases_, {}))
    ImGui_ImplGlfw_KeyCallback(window_, k.key, k.scancode, GLFW_RELEASE, k.mods);
  glfwSwapBuffers(window_);
  timings_.frame = ms_since(t_frame);

  if (frame_log_.enabled()) {
    FrameRecord r;
    r.frame = frame_index_;
    r.t_s = std::chrono::duration<double>(Clock::now() - start_).count();
    r.evaluate_ms = timings_.evaluate, r.detail_ms = timings_.detail;
    r.normals_ms = geometry ? timings_.normals : 0.0, r.upload_ms = geometry ? timings_.upload : 0.0;
    r.draw_ms = timings_.draw, r.ui_ms = timings_.ui, r.frame_ms = timings_.frame;
    r.vertices = doc_.has_mesh() ? doc_.rest_mesh().n_vertices() : 0;
    r.support = doc_.has_mesh() ? doc_.state().n_support() : 0;
    r.geometry = geometry;
    frame_log_.add(r);
  }
  ++frame_index_;
}

bool App::update_geometry(bool timed) {
  if (!doc_.has_mesh()) return false;
  FrameTimings ft;
  bool geometry = false;
  try {
    ft = doc_.update_display();
    timings_.evaluate = ft.evaluated ? ft.evaluate_ms : 0.0;
    timings_.detail = ft.evaluated ? ft.reconstruction_ms : 0.0;
    const Mesh& rest = doc_.rest_mesh();
    const VertexData<Vec3>& display = doc_.display_positions();
    const bool display_ok = static_cast<int>(display.size()) == rest.n_vertices();
    if (!scene_uploaded_ || scene_.n_vertices() != rest.n_vertices()) {
      scene_ = viewer::make_scene(rest, viewer::kPlainColor);
      if (display_ok) viewer::update_geometry(scene_, display);
      recolor();
      const auto t0 = Clock::now();
      renderer_->upload(scene_);
      if (timed) glFinish();
      timings_.upload = ms_since(t0);
      timings_.normals = 0.0;
      scene_uploaded_ = true;
      shown_display_version_ = doc_.display_version();
      shown_reset_version_ = doc_.display_reset_version();
      patch_ = viewer::GeometryPatch(scene_, doc_.display_touched());
      camera_.set_bounds(scene_.bounds);
      geometry = true;
    } else if (doc_.display_version() != shown_display_version_ && display_ok) {
      // Between resets only the solver's touched vertices move: O(support) (geometry_patch.h).
      const bool reset = doc_.display_reset_version() != shown_reset_version_;
      auto t0 = Clock::now();
      if (reset) {
        viewer::update_geometry(scene_, display);
        patch_ = viewer::GeometryPatch(scene_, doc_.display_touched());
        shown_reset_version_ = doc_.display_reset_version();
      } else {
        patch_.apply(scene_, display);
      }
      timings_.normals = ms_since(t0);
      t0 = Clock::now();
      if (reset)
        renderer_->update_geometry(scene_);
      else
        renderer_->update_geometry(scene_, patch_.ranges());
      if (timed) glFinish();
      timings_.upload = ms_since(t0);
      shown_display_version_ = doc_.display_version();
      camera_.set_bounds(scene_.bounds);
      geometry = true;
    }
    if (doc_.region_version() != shown_region_version_ || doc_.active_handle() != shown_active_handle_ ||
        band_shown() != shown_band_ || doc_.active_segment() != shown_active_segment_) {
      recolor();
      renderer_->update_colors(scene_);
    }
  } catch (const std::exception& e) {
    error(std::string("cannot display the mesh: ") + e.what());
  }
  // Failures of the background precomputation: one popup per new message.
  const std::string bg = doc_.last_error();
  if (!bg.empty() && bg != shown_background_error_) error("precomputation failed: " + bg);
  shown_background_error_ = bg;
  if (ft.evaluated) {
    status_timings_.evaluate = timings_.evaluate;
    status_timings_.detail = timings_.detail;
  }
  if (geometry) status_timings_.upload = timings_.upload;
  if (ft.evaluated || geometry) update_title();
  return geometry;
}

void App::fit_view() {
  if (!doc_.has_mesh()) return;
  const auto up = up_axis_ == 0 ? viewer::UpAxis::Z : viewer::UpAxis::Y;
  camera_.reset(scene_.bounds, kViewPresets[view_preset_], up, aspect());
}

}  // namespace freeform::editor
