#include "freeform/io/file_util.h"

#include "freeform/common/error.h"

#include <cerrno>
#include <cstdlib>
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

}  // namespace

std::string read_file(const std::string& path) {
  FdGuard guard;
  guard.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (guard.fd < 0) throw IoError(path, 0, "cannot open for reading: " + errno_message(errno));
  struct stat st {};
  if (::fstat(guard.fd, &st) != 0) throw IoError(path, 0, "cannot stat: " + errno_message(errno));
  if (S_ISDIR(st.st_mode)) throw IoError(path, 0, "is a directory, not a file");

  // Read straight into the string; a regular file's size is known, other files grow it.
  std::string data(S_ISREG(st.st_mode) && st.st_size > 0 ? static_cast<std::size_t>(st.st_size) + 1 : 1 << 16, '\0');
  std::size_t size = 0;
  for (;;) {
    if (size == data.size()) data.resize(2 * size);
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

void write_file_atomic(const std::string& path, std::string_view data) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  if (target.filename().empty()) throw IoError(path, 0, "cannot write: path names a folder, not a file");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");

  // mkstemp gives a unique name in the target's folder, so the final rename stays on one file system.
  std::string tmpl = (dir / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  std::vector<char> name(tmpl.begin(), tmpl.end());
  name.push_back('\0');
  FdGuard guard;
  guard.fd = ::mkstemp(name.data());
  if (guard.fd < 0)
    throw IoError(path, 0, "cannot create temporary file in '" + dir.string() + "': " + errno_message(errno));
  const std::string tmp(name.data());

  try {
    // Keep the mode of an existing target; new files get rw-r--r-- (mkstemp creates 0600).
    struct stat st {};
    const mode_t mode = ::stat(path.c_str(), &st) == 0 ? (st.st_mode & 07777) : 0644;
    if (::fchmod(guard.fd, mode) != 0) throw IoError(tmp, 0, "cannot set permissions: " + errno_message(errno));
    write_all(guard.fd, data, tmp);
    if (::fsync(guard.fd) != 0) throw IoError(tmp, 0, "cannot flush to disk: " + errno_message(errno));
    const int fd = guard.fd;
    guard.fd = -1;
    if (::close(fd) != 0) throw IoError(tmp, 0, "cannot close: " + errno_message(errno));
    if (::rename(tmp.c_str(), path.c_str()) != 0)
      throw IoError(path, 0, "cannot replace file: " + errno_message(errno));
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }

  // Best effort: make the rename itself durable.
  FdGuard dir_guard;
  dir_guard.fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_guard.fd >= 0) (void)::fsync(dir_guard.fd);
}

}  // namespace freeform
