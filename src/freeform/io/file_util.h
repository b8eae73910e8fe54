// Whole-file reading and atomic writing.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace freeform {

// Non-regular inputs (pipes, devices) are read up to this many bytes: an endless one such as
// /dev/zero is refused instead of growing until memory runs out.
inline constexpr std::size_t kMaxStreamBytes = std::size_t{256} << 20;

// The whole file; IoError naming the file if it cannot be opened or read, if it is a directory,
// a sparse file (mostly holes: not a mesh, and reading it would take its nominal size in memory)
// or a non-regular file longer than kMaxStreamBytes.
std::string read_file(const std::string& path);

// "-" (standard output) or an existing device, pipe or socket (/dev/null, /dev/stdout): written
// in place, never replaced by a rename.
bool is_special_file(const std::string& path);

// True if a and b name the same file (hard links, symlinks, "./x" and "x"); false if either
// does not exist and their normalized paths differ.
bool same_file(const std::string& a, const std::string& b);

// The folder `path` lies in ("." for a bare name): where the file's relative references resolve.
std::string folder_of(const std::string& path);

// How a file that `name` refers to from `from_folder` is named from `to_folder`: the relative
// path between them ('/'-separated); `name` itself where it is absolute or no such path exists.
// A file written into another folder than its input's keeps its references to other files
// (OBJ material libraries, PLY texture comments) working this way.
std::string reference_from(std::string_view name, const std::string& from_folder, const std::string& to_folder);

// Two-phase atomic write: the constructor writes `data` to a temporary file next to the target
// and flushes it; commit() renames it over the target. Uncommitted temporaries are removed by
// the destructor, and by SIGINT / SIGTERM / SIGHUP while they exist (when those signals have
// their default action). A symlinked target keeps its link: the file it points to is replaced.
// Special files (an existing device or pipe such as /dev/null, /dev/stdout, and "-" for standard
// output) are written directly at commit(), with no temporary. Throws IoError naming the file.
class PreparedFile {
 public:
  PreparedFile(const std::string& path, std::string_view data);
  ~PreparedFile();
  PreparedFile(const PreparedFile&) = delete;
  PreparedFile& operator=(const PreparedFile&) = delete;
  void commit();

 private:
  std::string path_;    // as given (messages)
  std::string target_;  // the file replaced: symlinks resolved
  std::string tmp_;     // empty for special files
  std::string data_;    // special files only: written at commit()
  int slot_ = -1;       // signal-cleanup registration of tmp_
  bool special_ = false;
  bool committed_ = false;
};

// PreparedFile(path, data).commit(): on any failure `path` is untouched and IoError is thrown.
void write_file_atomic(const std::string& path, std::string_view data);

}  // namespace freeform
