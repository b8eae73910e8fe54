// Internal helpers of the glTF reader and writers: the .glb container, base64 and data: URIs,
// percent-encoded file URIs, little-endian scalars and the schema check of the JSON.
// Not part of the public API.
#pragma once

#include "freeform/common/json_reader.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>

namespace freeform::gltf_detail {

// The chunks of a .glb: the JSON text, the BIN chunk (if any) and the chunks after it, verbatim
// (unknown chunk types must be kept by a writer that does not understand them).
struct Glb {
  std::string_view json;
  std::optional<std::string_view> bin;
  std::string_view rest;
};

inline bool is_glb(std::string_view data) { return data.substr(0, 4) == "glTF"; }
// Throws IoError(path, 0, ...) on a malformed or truncated container.
Glb parse_glb(std::string_view data, const std::string& path);
// A .glb holding `json` (padded with spaces), `bin` (padded with zeros; none when empty and
// `has_bin` is false) and `rest` (whole chunks, copied).
std::string build_glb(std::string_view json, std::string_view bin, bool has_bin, std::string_view rest = {});

std::string base64_encode(std::string_view bytes);
std::optional<std::string> base64_decode(std::string_view text);  // nullopt on a bad character

inline bool is_data_uri(std::string_view uri) { return uri.substr(0, 5) == "data:"; }
// "data:...;base64," of a data URI (empty if it is not base64) and its decoded bytes;
// nullopt when it cannot be decoded (`error` says why).
struct DataUri {
  std::string prefix;
  std::string bytes;
};
std::optional<DataUri> decode_data_uri(std::string_view uri, std::string& error);

// %XX escapes of a relative URI decoded; false when one is malformed.
bool uri_decode(std::string_view uri, std::string& out);
// A file name as a relative URI reference (unreserved bytes kept, others %XX).
std::string uri_encode(std::string_view name);
// True for "scheme:..." URIs (http:, file:) and absolute paths: not files beside the glTF.
bool is_remote_or_absolute(std::string_view uri);

template <class T>
T load_le(const unsigned char* p) {
  static_assert(std::endian::native == std::endian::little, "glTF buffers are little endian");
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}
template <class T>
void store_le(unsigned char* p, T value) {
  static_assert(std::endian::native == std::endian::little, "glTF buffers are little endian");
  std::memcpy(p, &value, sizeof(T));
}

// Checks the types of every property of the glTF 2.0 core schema (objects, arrays, numbers,
// strings, indices into the top-level arrays, required properties), also of the parts the
// reader does not use: a file a viewer would refuse is refused before it is rewritten.
// Throws IoError(path, 0, "materials[0].normalTexture.scale must be a number, got a string").
void check_schema(const Json& root, const std::string& path);

// The deepest nesting of arrays and objects in a JSON text (strings skipped). Copying and
// writing nlohmann's values recurses once per level, so deep texts are refused before parsing.
std::size_t json_depth(std::string_view text);

// The JSON text of `j` in the layout of `original`: compact when it had no line break,
// otherwise indented like its second line; a final line break kept.
std::string dump_like(const Json& j, std::string_view original);

}  // namespace freeform::gltf_detail
