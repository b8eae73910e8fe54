#include "freeform/io/obj_libraries.h"

#include "freeform/io/file_util.h"

#include <filesystem>
#include <string_view>
#include <system_error>

namespace freeform::io_detail {
namespace {

namespace fs = std::filesystem;

bool blank(char c) { return c == ' ' || c == '\t'; }
bool separator(char c) { return blank(c) || c == '\r' || c == '\n'; }

bool has_blank(const std::string& s) {
  for (const char c : s)
    if (blank(c)) return true;
  return false;
}

// The name by which the file `name` (relative to in_folder) is found from out_folder.
std::string relinked(std::string_view name, const fs::path& in_folder, const fs::path& out_folder) {
  const fs::path original(name);
  if (original.is_absolute()) return std::string(name);
  std::error_code ec;
  const fs::path target = fs::absolute(in_folder / original, ec).lexically_normal();
  if (ec) return std::string(name);
  const fs::path relative = fs::relative(target, out_folder, ec);
  if (!ec && !relative.empty() && !has_blank(relative.generic_string())) return relative.generic_string();
  return has_blank(target.generic_string()) ? std::string(name) : target.generic_string();
}

// One `mtllib` statement's names relinked; any other line as it is.
std::string relinked_line(std::string_view line, const fs::path& in_folder, const fs::path& out_folder) {
  std::size_t i = 0;
  while (i < line.size() && blank(line[i])) ++i;
  constexpr std::string_view kKeyword = "mtllib";
  if (line.substr(i, kKeyword.size()) != kKeyword || i + kKeyword.size() >= line.size() ||
      !blank(line[i + kKeyword.size()]))
    return std::string(line);
  std::string out(line.substr(0, i + kKeyword.size()));
  for (std::size_t k = i + kKeyword.size(); k < line.size();) {
    if (separator(line[k])) {
      out += line[k++];
      continue;
    }
    std::size_t end = k;
    while (end < line.size() && !separator(line[end])) ++end;
    out += relinked(line.substr(k, end - k), in_folder, out_folder);
    k = end;
  }
  return out;
}

}  // namespace

std::string relink_material_libraries(std::string text, const std::string& in_folder, const std::string& out_path) {
  const std::string out_folder = folder_of(out_path);
  if (same_file(in_folder.empty() ? "." : in_folder, out_folder)) return text;
  std::error_code ec;
  const fs::path out_absolute = fs::absolute(out_folder, ec).lexically_normal();
  std::string out;
  out.reserve(text.size());
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    end = end == std::string::npos ? text.size() : end + 1;
    out += relinked_line(std::string_view(text).substr(begin, end - begin), in_folder, out_absolute);
    begin = end;
  }
  return out;
}

}  // namespace freeform::io_detail
