#include "x_session.h"

#include <csignal>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace freeform::test {
namespace {

using namespace std::chrono_literals;

// fork + exec with extra environment entries; stdout/stderr go to `log` (appended).
int spawn(const std::vector<std::string>& argv, const std::vector<std::string>& env, const std::string& log) {
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    for (const std::string& e : env) putenv(const_cast<char*>(e.c_str()));
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

void kill_and_reap(int& pid) {
  if (pid <= 0) return;
  kill(pid, SIGTERM);
  for (int i = 0; i < 50; ++i) {
    if (waitpid(pid, nullptr, WNOHANG) == pid) {
      pid = -1;
      return;
    }
    std::this_thread::sleep_for(100ms);
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  pid = -1;
}

}  // namespace

// Xvfb picks a free display number itself and writes it to the pipe (-displayfd): no race with
// other X servers starting at the same time (parallel tests, a developer's own Xvfb).
XSession::XSession(int width, int height) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  const std::string screen = std::to_string(width) + "x" + std::to_string(height) + "x24";
  xvfb_pid_ = spawn({"Xvfb", "-displayfd", std::to_string(fds[1]), "-screen", "0", screen, "-nolisten", "tcp"}, {},
                    "/dev/null");
  close(fds[1]);
  std::string number;
  pollfd p{fds[0], POLLIN, 0};
  while (poll(&p, 1, 20000) > 0) {
    char c = 0;
    if (read(fds[0], &c, 1) != 1 || c == '\n') break;
    number += c;
  }
  close(fds[0]);
  if (number.empty()) {
    kill_and_reap(xvfb_pid_);
    throw std::runtime_error("could not start Xvfb (is the xvfb package installed?)");
  }
  display_ = ":" + number;
  for (int i = 0; i < 100; ++i) {
    if (shell("xdpyinfo >/dev/null 2>&1") == 0) return;
    std::this_thread::sleep_for(100ms);
  }
  kill_and_reap(xvfb_pid_);
  throw std::runtime_error("Xvfb on " + display_ + " does not answer (xdpyinfo, package x11-utils)");
}

XSession::~XSession() {
  kill_and_reap(editor_pid_);
  kill_and_reap(xvfb_pid_);
}

bool XSession::start_editor(const std::string& exe, const std::vector<std::string>& args,
                            const std::filesystem::path& home, std::chrono::seconds timeout) {
  std::vector<std::string> argv{exe};
  argv.insert(argv.end(), args.begin(), args.end());
  editor_pid_ = spawn(argv, {"DISPLAY=" + display_, "HOME=" + home.string(), "XDG_CONFIG_HOME=" + (home / ".config").string()},
                      (home / "editor.log").string());
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (!editor_running()) return false;
    if (shell("xdotool search --onlyvisible --name freeform >/dev/null 2>&1") == 0) return true;
    std::this_thread::sleep_for(200ms);
  }
  return false;
}

bool XSession::editor_running() {
  if (editor_pid_ <= 0) return false;
  int status = 0;
  if (waitpid(editor_pid_, &status, WNOHANG) == editor_pid_) {
    editor_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    editor_pid_ = -1;
    return false;
  }
  return true;
}

bool XSession::wait_editor_exit(std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    if (!editor_running()) return true;
    std::this_thread::sleep_for(100ms);
  }
  return false;
}

bool XSession::xdotool(const std::string& args) const { return shell("xdotool " + args) == 0; }

int XSession::shell(const std::string& command) const {
  const std::string full = "DISPLAY=" + display_ + " " + command;
  const int status = std::system(full.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace freeform::test
