// A virtual X display (Xvfb) with one freeform-editor window, driven by xdotool: the harness
// of the end-to-end editor tests. Processes are started with fork/exec and killed (and reaped)
// by the destructor; every wait has a timeout so a hung editor fails the test instead of CI.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace freeform::test {

class XSession {
 public:
  // Starts Xvfb on a free display number with a screen of width x height x 24.
  XSession(int width, int height);
  ~XSession();
  XSession(const XSession&) = delete;
  XSession& operator=(const XSession&) = delete;

  const std::string& display() const { return display_; }  // ":N"

  // Starts the editor with `args` (HOME and XDG_CONFIG_HOME set to `home`) and waits until its
  // window is mapped; returns false after the timeout.
  bool start_editor(const std::string& exe, const std::vector<std::string>& args, const std::filesystem::path& home,
                    std::chrono::seconds timeout = std::chrono::seconds(60));
  bool editor_running();  // false once it exited (exit_code() tells how)
  int exit_code() const { return editor_status_; }
  // Waits for the editor to exit by itself; false after the timeout.
  bool wait_editor_exit(std::chrono::seconds timeout);

  // xdotool commands (e.g. "mousemove 600 400 click 1", "key ctrl+z", "type --delay 20 text").
  // Coordinates are screen coordinates; the editor's window is at the top-left corner.
  bool xdotool(const std::string& args) const;
  // Runs a shell command with DISPLAY set; returns its exit status.
  int shell(const std::string& command) const;

 private:
  std::string display_;
  int xvfb_pid_ = -1;
  int editor_pid_ = -1;
  int editor_status_ = -1;
};

}  // namespace freeform::test
