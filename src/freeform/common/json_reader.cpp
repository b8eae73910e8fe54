#include "freeform/common/json_reader.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <vector>

namespace freeform {
namespace {

using json_messages::index_path;
using json_messages::key_path;
using json_messages::quoted;
using json_messages::type_of;

// 1-based line and column of byte offset `pos` in `text`.
std::pair<std::size_t, std::size_t> line_column(std::string_view text, std::size_t pos) {
  std::size_t line = 1, col = 1;
  for (std::size_t i = 0; i < std::min(pos, text.size()); ++i) {
    col = text[i] == '\n' ? 1 : col + 1;
    line += text[i] == '\n' ? 1 : 0;
  }
  return {line, col};
}

void write_json(std::string& out, const Json& j, int level, int expanded) {
  const bool container = j.is_object() || j.is_array();
  const bool scalars = j.is_array() && std::none_of(j.begin(), j.end(), [](const Json& e) { return e.is_structured(); });
  if (!container || j.empty() || scalars || level >= expanded) {
    out += j.dump();
    return;
  }
  const std::string pad(static_cast<std::size_t>(2 * (level + 1)), ' ');
  out += j.is_object() ? "{\n" : "[\n";
  std::size_t i = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++i) {
    out += pad;
    if (j.is_object()) out += Json(it.key()).dump() + ": ";
    write_json(out, *it, level + 1, expanded);
    out += i + 1 < j.size() ? ",\n" : "\n";
  }
  out += std::string(static_cast<std::size_t>(2 * level), ' ') + (j.is_object() ? "}" : "]");
}

}  // namespace

Json parse_json_text(std::string_view text, const std::string& name) {
  // nlohmann keeps the last of repeated keys silently; a strict reader refuses them.
  std::vector<std::vector<std::string>> seen;  // keys of each open object
  std::string duplicate;
  const Json::parser_callback_t check_duplicates = [&](int, Json::parse_event_t event, Json& parsed) {
    if (event == Json::parse_event_t::object_start) seen.emplace_back();
    if (event == Json::parse_event_t::object_end && !seen.empty()) seen.pop_back();
    if (event == Json::parse_event_t::key && !seen.empty() && duplicate.empty()) {
      const std::string key = parsed.get<std::string>();
      if (std::find(seen.back().begin(), seen.back().end(), key) != seen.back().end()) duplicate = key;
      seen.back().push_back(key);
    }
    return true;
  };
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos) {
    // nlohmann's parser stops at a NUL and would accept whatever garbage follows it.
    const auto [line, col] = line_column(text, nul);
    throw IoError(name, line, "NUL byte at column " + std::to_string(col) + " (not JSON text)");
  }
  Json j;
  try {
    j = Json::parse(text, check_duplicates);
  } catch (const Json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character.
    const auto [line, col] = line_column(text, e.byte > 0 ? e.byte - 1 : 0);
    std::string reason = e.what();
    const std::size_t colon = reason.find(": ", reason.find("parse error"));
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
    throw IoError(name, line, "malformed JSON at column " + std::to_string(col) + ": " + reason);
  } catch (const Json::exception& e) {  // e.g. a number too large for a double
    std::string reason = e.what();
    const std::size_t bracket = reason.find("] ");
    if (bracket != std::string::npos) reason = reason.substr(bracket + 2);
    throw IoError(name, 0, "malformed JSON: " + reason);
  }
  if (!duplicate.empty()) throw InvalidInput(name + ": the key \"" + duplicate + "\" appears twice in one object");
  return j;
}

std::string json_text(const Json& j, int expanded_levels) {
  std::string out;
  write_json(out, j, 0, expanded_levels);
  return out + "\n";
}

void JsonReader::fail(const std::string& message) const { throw InvalidInput(name_ + ": " + message); }

const Json& JsonReader::required(const Json& obj, const std::string& path, const char* key) const {
  if (!obj.contains(key)) fail("missing required key " + quoted(key_path(path, key)));
  return obj[key];
}

void JsonReader::keys(const Json& obj, const std::string& path, std::initializer_list<const char*> allowed) const {
  keys(obj, path, std::span<const char* const>(allowed.begin(), allowed.size()));
}

void JsonReader::keys(const Json& obj, const std::string& path, std::span<const char* const> allowed) const {
  for (const auto& item : obj.items()) {
    const std::string& key = item.key();  // not a structured binding: clang 14 cannot capture those
    if (std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return key == a; })) continue;
    std::string list;
    for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + "\"" + a + "\"";
    fail("unknown key " + quoted(key_path(path, key)) + " (allowed here: " + list + ")");
  }
}

void JsonReader::object(const Json& j, const std::string& path) const {
  if (!j.is_object()) fail(quoted(path) + " must be an object, got " + type_of(j));
}

const Json& JsonReader::array(const Json& j, const std::string& path) const {
  if (!j.is_array()) fail(quoted(path) + " must be an array, got " + type_of(j));
  return j;
}

long long JsonReader::integer(const Json& j, const std::string& path) const {
  if (j.is_number_unsigned())
    return static_cast<long long>(std::min<unsigned long long>(j.get<unsigned long long>(), LLONG_MAX));
  if (!j.is_number_integer()) fail(quoted(path) + " must be an integer, got " + type_of(j));
  return j.get<long long>();
}

double JsonReader::number(const Json& j, const std::string& path) const {
  if (!j.is_number()) fail(quoted(path) + " must be a number, got " + type_of(j));
  const double x = j.get<double>();
  if (!std::isfinite(x)) fail(quoted(path) + " must be finite");
  return x;
}

bool JsonReader::boolean(const Json& j, const std::string& path) const {
  if (!j.is_boolean()) fail(quoted(path) + " must be true or false, got " + type_of(j));
  return j.get<bool>();
}

std::string JsonReader::string(const Json& j, const std::string& path) const {
  if (!j.is_string()) fail(quoted(path) + " must be a string, got " + type_of(j));
  const std::string& s = j.get_ref<const std::string&>();
  // A file name cut at a NUL would name another file ("a.sel\u0000.junk" reads a.sel).
  if (s.find('\0') != std::string::npos) fail(quoted(path) + " contains a NUL byte");
  return s;
}

Eigen::Vector3d JsonReader::vec3(const Json& j, const std::string& path) const {
  if (!j.is_array() || j.size() != 3) fail(quoted(path) + " must be an array of 3 numbers [x, y, z]");
  return {number(j[0], index_path(path, 0)), number(j[1], index_path(path, 1)), number(j[2], index_path(path, 2))};
}

Eigen::Matrix4d JsonReader::matrix4(const Json& j, const std::string& path) const {
  if (!j.is_array() || j.size() != 4) fail(quoted(path) + " must be 4 rows of 4 numbers (row-major)");
  Eigen::Matrix4d m;
  for (std::size_t r = 0; r < 4; ++r) {
    const std::string rp = index_path(path, r);
    if (!j[r].is_array() || j[r].size() != 4) fail(quoted(rp) + " must be a row of 4 numbers");
    for (std::size_t c = 0; c < 4; ++c) m(static_cast<int>(r), static_cast<int>(c)) = number(j[r][c], index_path(rp, c));
  }
  return m;
}

}  // namespace freeform
