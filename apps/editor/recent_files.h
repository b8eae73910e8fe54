// The editor's list of recently opened meshes, persisted as JSON in
// $XDG_CONFIG_HOME/freeform/recent.json (or ~/.config/freeform/recent.json):
//   {"recent": ["/abs/path/a.off", ...]}   most recent first, at most kMaxEntries.
// A missing or unreadable or corrupt file is ignored (the list starts empty); saving is atomic.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace freeform::editor {

class RecentFiles {
 public:
  static constexpr std::size_t kMaxEntries = 10;

  // Where the list lives by default; empty if neither XDG_CONFIG_HOME nor HOME is set.
  static std::filesystem::path default_location();

  RecentFiles() = default;
  explicit RecentFiles(std::filesystem::path file) : file_(std::move(file)) {}

  // Reads the file; anything wrong (missing, not JSON, wrong shape) leaves the list empty.
  void load();
  // Writes atomically, creating the folder. Throws IoError on failure (the caller reports it).
  void save() const;

  // Moves `path` (made absolute) to the front; drops duplicates and the oldest beyond the limit.
  void add(const std::string& path);
  void remove(const std::string& path);
  const std::vector<std::string>& entries() const { return entries_; }
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  std::vector<std::string> entries_;
};

}  // namespace freeform::editor
