#include "recent_files.h"

#include "freeform/common/error.h"
#include "freeform/io/file_util.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <system_error>

namespace freeform::editor {

std::filesystem::path RecentFiles::default_location() {
  const char* xdg = std::getenv("XDG_CONFIG_HOME");
  if (xdg && *xdg == '/') return std::filesystem::path(xdg) / "freeform" / "recent.json";
  const char* home = std::getenv("HOME");
  if (home && *home) return std::filesystem::path(home) / ".config" / "freeform" / "recent.json";
  return {};
}

void RecentFiles::load() {
  entries_.clear();
  if (file_.empty()) return;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file_, ec)) return;
  try {
    const nlohmann::json j = nlohmann::json::parse(read_file(file_.string()));
    if (!j.is_object() || !j.contains("recent") || !j["recent"].is_array()) return;
    for (const auto& item : j["recent"]) {
      if (!item.is_string()) continue;
      const std::string path = item.get<std::string>();
      if (!path.empty() && std::find(entries_.begin(), entries_.end(), path) == entries_.end()) entries_.push_back(path);
      if (entries_.size() == kMaxEntries) break;
    }
  } catch (const std::exception&) {  // corrupt or unreadable: start empty
    entries_.clear();
  }
}

void RecentFiles::save() const {
  if (file_.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(file_.parent_path(), ec);
  if (ec) throw IoError(file_.parent_path().string(), 0, "cannot create the folder for the recent files: " + ec.message());
  write_file_atomic(file_.string(), nlohmann::json{{"recent", entries_}}.dump(2) + "\n");
}

void RecentFiles::add(const std::string& path) {
  std::error_code ec;
  std::filesystem::path abs = std::filesystem::absolute(path, ec);
  const std::string key = ec ? path : abs.lexically_normal().string();
  remove(key);
  entries_.insert(entries_.begin(), key);
  if (entries_.size() > kMaxEntries) entries_.resize(kMaxEntries);
}

void RecentFiles::remove(const std::string& path) {
  entries_.erase(std::remove(entries_.begin(), entries_.end(), path), entries_.end());
}

}  // namespace freeform::editor
