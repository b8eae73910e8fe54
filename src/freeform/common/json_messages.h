// Wording shared by the strict JSON readers (edit files, editor sessions): key paths such as
// handles[0].transform and "what was found" descriptions for their error messages.
#pragma once

#include <cstddef>
#include <sstream>
#include <string>

namespace freeform::json_messages {

inline std::string num(double x) {
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}
inline std::string key_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}
inline std::string index_path(const std::string& parent, std::size_t i) { return parent + "[" + std::to_string(i) + "]"; }
// Control characters are escaped (\u0000): a NUL in a key must not cut the message short.
inline std::string quoted(const std::string& path) {
  std::string out = "\"";
  for (const char c : path) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
      continue;
    }
    constexpr char kHex[] = "0123456789abcdef";
    out += "\\u00";
    out += kHex[u >> 4];
    out += kHex[u & 15];
  }
  return out + "\"";
}

// "the integer 3", "a string", ... for any nlohmann::basic_json.
template <class Json>
std::string type_of(const Json& j) {
  if (j.is_number_integer()) return "the integer " + j.dump();
  if (j.is_number()) return "the number " + j.dump();
  if (j.is_string()) return "a string";
  if (j.is_boolean()) return j.dump();
  if (j.is_null()) return "null";
  return j.is_array() ? "an array" : "an object";
}

}  // namespace freeform::json_messages
