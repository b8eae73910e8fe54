#include "freeform/io/file_util.h"

#include "freeform/common/error.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace freeform {
namespace {

std::string errno_message(int err) { return std::error_code(err, std::generic_category()).message(); }

// Closes the descriptor when it goes out of scope (errors of this close are irrelevant).
struct FdGuard {
  int fd = -1;
  ~FdGuard() {
    if (fd >= 0) ::close(fd);
  }
};

void write_all(int fd, std::string_view data, const std::string& tmp) {
  const char* p = data.data();
  std::size_t left = data.size();
  while (left > 0) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError(tmp, 0, "cannot write: " + errno_message(errno));
    }
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

// Temporaries a signal must remove: fixed slots, so the handler needs no allocation or lock.
struct TempSlot {
  std::atomic<int> state{0};  // 0 free, 1 being set, 2 live
  std::array<char, 4096> path{};
};
std::array<TempSlot, 16> g_temps;

extern "C" void remove_temps_and_reraise(int sig) {
  for (TempSlot& t : g_temps)
    if (t.state.load() == 2) ::unlink(t.path.data());  // async-signal-safe
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Checked at every registration (cheap next to writing a file): an application may reset a
// signal to its default later; its own handlers are left alone.
void install_cleanup_handlers() {
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0 || (old.sa_flags & SA_SIGINFO) || old.sa_handler != SIG_DFL) continue;
    struct sigaction sa {};
    sa.sa_handler = remove_temps_and_reraise;
    sigemptyset(&sa.sa_mask);
    ::sigaction(sig, &sa, nullptr);
  }
}

// Registers a temporary for removal on a signal; returns its slot (-1 if all are taken or the
// path is too long: then only the normal paths remove it).
int register_temp(const std::string& tmp) {
  install_cleanup_handlers();
  if (tmp.size() >= std::tuple_size_v<decltype(TempSlot::path)>) return -1;
  for (std::size_t i = 0; i < g_temps.size(); ++i) {
    int expected = 0;
    if (!g_temps[i].state.compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_temps[i].path.data(), tmp.c_str(), tmp.size() + 1);
    g_temps[i].state.store(2);
    return static_cast<int>(i);
  }
  return -1;
}

void unregister_temp(int slot) {
  if (slot >= 0) g_temps[static_cast<std::size_t>(slot)].state.store(0);
}

// Bytes of a file that are data rather than holes (SEEK_DATA / SEEK_HOLE; a file system without
// them reports one data extent, so nothing looks sparse there).
off_t data_bytes(int fd, off_t size) {
  off_t total = 0, pos = 0;
  while (pos < size) {
    const off_t start = ::lseek(fd, pos, SEEK_DATA);
    if (start < 0) {
      if (errno == ENXIO) break;  // only holes remain
      total = size;               // no verdict where the file system cannot tell
      break;
    }
    const off_t end = ::lseek(fd, start, SEEK_HOLE);
    if (end < 0) return size;
    total += end - start;
    pos = end;
  }
  ::lseek(fd, 0, SEEK_SET);
  return total;
}

}  // namespace

std::string read_file(const std::string& path) {
  FdGuard guard;
  guard.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (guard.fd < 0) throw IoError(path, 0, "cannot open for reading: " + errno_message(errno));
  struct stat st {};
  if (::fstat(guard.fd, &st) != 0) throw IoError(path, 0, "cannot stat: " + errno_message(errno));
  if (S_ISDIR(st.st_mode)) throw IoError(path, 0, "is a directory, not a file");
  const bool regular = S_ISREG(st.st_mode);
  if (regular && static_cast<std::size_t>(st.st_size) > kMaxStreamBytes) {
    const off_t data = data_bytes(guard.fd, st.st_size);
    if (data * 64 < st.st_size)
      throw IoError(path, 0, "is a sparse file (" + std::to_string(st.st_size) + " bytes, " + std::to_string(data) +
                                 " of them data): not a mesh, refused instead of reading its holes into memory");
  }

  // Read straight into the string; a regular file's size is known, other files grow it.
  std::string data(regular && st.st_size > 0 ? static_cast<std::size_t>(st.st_size) + 1 : 1 << 16, '\0');
  std::size_t size = 0;
  for (;;) {
    if (size == data.size()) {
      if (!regular && size >= kMaxStreamBytes)
        throw IoError(path, 0, "is not a regular file and did not end within " + std::to_string(kMaxStreamBytes >> 20) +
                                   " MiB (an endless device such as /dev/zero?); save the mesh to a file first");
      data.resize(regular ? 2 * size : std::min(2 * size, kMaxStreamBytes));
    }
    const ssize_t n = ::read(guard.fd, data.data() + size, data.size() - size);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw IoError(path, 0, "cannot read: " + errno_message(errno));
    }
    if (n == 0) break;
    size += static_cast<std::size_t>(n);
  }
  data.resize(size);
  return data;
}

bool is_special_file(const std::string& path) {
  if (path == "-") return true;
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  const fs::path ca = fs::weakly_canonical(a, ec);
  if (ec) return false;
  const fs::path cb = fs::weakly_canonical(b, ec);
  return !ec && ca == cb;
}

std::string folder_of(const std::string& path) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  return folder.empty() ? std::string(".") : folder.string();
}

std::string reference_from(std::string_view name, const std::string& from_folder, const std::string& to_folder) {
  namespace fs = std::filesystem;
  const fs::path original(name);
  if (original.is_absolute()) return std::string(name);
  std::error_code ec;
  const fs::path target = fs::absolute(fs::path(from_folder) / original, ec).lexically_normal();
  if (ec) return std::string(name);
  const fs::path relative = fs::relative(target, fs::absolute(to_folder, ec).lexically_normal(), ec);
  return ec || relative.empty() ? std::string(name) : relative.generic_string();
}

PreparedFile::PreparedFile(const std::string& path, std::string_view data) : path_(path) {
  namespace fs = std::filesystem;
  if (is_special_file(path)) {
    special_ = true;
    data_ = data;
    return;
  }
  // Follow a chain of links by hand: a dangling link's target is created, not the link replaced.
  fs::path target(path);
  std::error_code ec;
  for (int depth = 0; fs::is_symlink(fs::symlink_status(target, ec)); ++depth) {
    if (depth == 40) throw IoError(path, 0, "cannot write: too many levels of symbolic links");
    const fs::path next = fs::read_symlink(target, ec);
    if (ec) throw IoError(path, 0, "cannot resolve the symbolic link: " + ec.message());
    target = next.is_absolute() ? next : target.parent_path() / next;
  }
  if (target.filename().empty()) throw IoError(path, 0, "cannot write: path names a folder, not a file");
  target_ = target.string();
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");

  // mkstemp gives a unique name in the target's folder, so the final rename stays on one file system.
  std::string tmpl = (dir / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  FdGuard guard;
  guard.fd = ::mkstemp(name.data());
  if (guard.fd < 0)
    throw IoError(path, 0, "cannot create temporary file in '" + dir.string() + "': " + errno_message(errno));
  tmp_ = name.data();
  slot_ = register_temp(tmp_);
  try {
    // Keep the mode of an existing target; new files get rw-r--r-- (mkstemp creates 0600).
    struct stat st {};
    const mode_t mode = ::stat(target_.c_str(), &st) == 0 ? (st.st_mode & 07777) : 0644;
    if (::fchmod(guard.fd, mode) != 0) throw IoError(tmp_, 0, "cannot set permissions: " + errno_message(errno));
    write_all(guard.fd, data, tmp_);
    if (::fsync(guard.fd) != 0) throw IoError(tmp_, 0, "cannot flush to disk: " + errno_message(errno));
    const int fd = guard.fd;
    guard.fd = -1;
    if (::close(fd) != 0) throw IoError(tmp_, 0, "cannot close: " + errno_message(errno));
  } catch (...) {
    ::unlink(tmp_.c_str());
    unregister_temp(slot_);
    throw;
  }
}

PreparedFile::~PreparedFile() {
  if (!special_ && !committed_) ::unlink(tmp_.c_str());
  unregister_temp(slot_);
}

void PreparedFile::commit() {
  if (committed_) return;
  if (special_) {
    FdGuard guard;
    if (path_ == "-") {
      write_all(STDOUT_FILENO, data_, "standard output");
    } else {
      guard.fd = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
      if (guard.fd < 0) throw IoError(path_, 0, "cannot open for writing: " + errno_message(errno));
      write_all(guard.fd, data_, path_);
    }
    committed_ = true;
    return;
  }
  if (::rename(tmp_.c_str(), target_.c_str()) != 0)
    throw IoError(path_, 0, "cannot replace file: " + errno_message(errno));
  committed_ = true;
  unregister_temp(slot_);
  slot_ = -1;
  // Best effort: make the rename itself durable.
  const std::filesystem::path target(target_);
  FdGuard dir_guard;
  dir_guard.fd = ::open(target.has_parent_path() ? target.parent_path().c_str() : ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_guard.fd >= 0) (void)::fsync(dir_guard.fd);
}

void write_file_atomic(const std::string& path, std::string_view data) { PreparedFile(path, data).commit(); }

}  // namespace freeform
