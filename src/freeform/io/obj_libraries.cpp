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

// The name by which the library `name` (relative to in_folder) is found from out_folder: a
// relative path, or absolute where that would hold a blank (blanks separate OBJ's names).
std::string relinked(std::string_view name, const std::string& in_folder, const std::string& out_folder) {
  const std::string relative = reference_from(name, in_folder, out_folder);
  if (!has_blank(relative)) return relative;
  std::error_code ec;
  const std::string absolute =
      fs::absolute(fs::path(in_folder) / fs::path(name), ec).lexically_normal().generic_string();
  return ec || has_blank(absolute) ? std::string(name) : absolute;
}

// One `mtllib` statement's names relinked; any other line as it is.
std::string relinked_line(std::string_view line, const std::string& in_folder, const std::string& out_folder) {
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
  if (same_file(in_folder, out_folder)) return text;
  std::string out;
  out.reserve(text.size());
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    end = end == std::string::npos ? text.size() : end + 1;
    out += relinked_line(std::string_view(text).substr(begin, end - begin), in_folder, out_folder);
    begin = end;
  }
  return out;
}

}  // namespace freeform::io_detail
