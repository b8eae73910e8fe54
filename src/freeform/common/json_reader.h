// The one strict JSON reader of the project's files (edit files, editor sessions): parse errors
// give FILE:LINE and the column, a key repeated in one object is refused, and JsonReader's typed
// getters refuse wrong types, unknown keys, missing keys and non-finite numbers with messages
// "NAME: what is wrong at KEY.PATH" (InvalidInput). Also the project's JSON text writer.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <initializer_list>
#include <span>
#include <string>
#include <string_view>

namespace freeform {

using Json = nlohmann::ordered_json;  // keeps the file's key order (messages, round trips)

// Parses `text` strictly. Malformed JSON: IoError(name, line, "malformed JSON at column C: ...");
// a key that appears twice in one object: InvalidInput naming it.
Json parse_json_text(std::string_view text, const std::string& name);

// Text of `j` with containers down to `expanded_levels` one element per line and deeper ones
// (and arrays of scalars) on one line; doubles keep full round-trip precision. Ends with "\n".
std::string json_text(const Json& j, int expanded_levels = 2);

class JsonReader {
 public:
  explicit JsonReader(std::string name) : name_(std::move(name)) {}
  const std::string& name() const { return name_; }

  [[noreturn]] void fail(const std::string& message) const;  // InvalidInput "NAME: message"

  const Json& required(const Json& obj, const std::string& path, const char* key) const;
  // Fails on the first key of `obj` not in `allowed`, listing the allowed ones.
  void keys(const Json& obj, const std::string& path, std::initializer_list<const char*> allowed) const;
  void keys(const Json& obj, const std::string& path, std::span<const char* const> allowed) const;
  void object(const Json& j, const std::string& path) const;
  const Json& array(const Json& j, const std::string& path) const;
  long long integer(const Json& j, const std::string& path) const;  // unsigned values saturate
  double number(const Json& j, const std::string& path) const;      // finite
  bool boolean(const Json& j, const std::string& path) const;
  std::string string(const Json& j, const std::string& path) const;
  Eigen::Vector3d vec3(const Json& j, const std::string& path) const;  // [x, y, z]
  Eigen::Matrix4d matrix4(const Json& j, const std::string& path) const;  // 4 rows of 4, row-major

 private:
  std::string name_;
};

}  // namespace freeform
