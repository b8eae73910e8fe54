#include "freeform/io/gltf_util.h"

#include "freeform/common/error.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>

namespace freeform::gltf_detail {
namespace {

constexpr std::uint32_t kJsonChunk = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kBinChunk = 0x004E4942;   // "BIN\0"

std::uint32_t u32(std::string_view data, std::size_t at) {
  return load_le<std::uint32_t>(reinterpret_cast<const unsigned char*>(data.data() + at));
}

void put_u32(std::string& out, std::uint32_t v) {
  unsigned char b[4];
  store_le(b, v);
  out.append(reinterpret_cast<const char*>(b), 4);
}

void put_chunk(std::string& out, std::uint32_t type, std::string_view bytes, char pad) {
  const std::size_t padded = (bytes.size() + 3) / 4 * 4;
  put_u32(out, static_cast<std::uint32_t>(padded));
  put_u32(out, type);
  out.append(bytes);
  out.append(padded - bytes.size(), pad);
}

constexpr char kBase64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+' || c == '-') return 62;  // '-' and '_': the URL-safe alphabet
  if (c == '/' || c == '_') return 63;
  return -1;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

Glb parse_glb(std::string_view data, const std::string& path) {
  if (data.size() < 12) throw IoError(path, 0, fmt::format("file truncated: {} bytes, a .glb header needs 12", data.size()));
  if (const std::uint32_t version = u32(data, 4); version != 2)
    throw IoError(path, 0, fmt::format(".glb version {} (only glTF 2 is supported)", version));
  const std::uint32_t length = u32(data, 8);
  if (length != data.size())
    throw IoError(path, 0,
                  fmt::format("{}: header declares {} bytes, the file has {}",
                              length > data.size() ? "file truncated" : "length mismatch", length, data.size()));
  Glb glb;
  std::size_t at = 12;
  for (int chunk = 0; at < data.size(); ++chunk) {
    if (data.size() - at < 8) throw IoError(path, 0, fmt::format("file truncated in the header of chunk {}", chunk));
    const std::uint32_t size = u32(data, at), type = u32(data, at + 4);
    if (size > data.size() - at - 8)
      throw IoError(path, 0, fmt::format("file truncated: chunk {} declares {} bytes, {} remain", chunk, size,
                                         data.size() - at - 8));
    const std::string_view bytes = data.substr(at + 8, size);
    if (chunk == 0 && type != kJsonChunk) throw IoError(path, 0, "the first chunk of a .glb is not JSON");
    if (chunk == 0) glb.json = bytes;
    if (chunk == 1 && type == kBinChunk) glb.bin = bytes;
    if (chunk >= 1 && !(chunk == 1 && type == kBinChunk)) {
      glb.rest = data.substr(at);  // unknown chunks: kept whole, in order
      break;
    }
    at += 8 + std::size_t{size};
  }
  if (at == 12) throw IoError(path, 0, "no JSON chunk");
  return glb;
}

std::string build_glb(std::string_view json, std::string_view bin, bool has_bin, std::string_view rest) {
  std::string out = "glTF";
  put_u32(out, 2);
  put_u32(out, 0);  // total length, set below
  put_chunk(out, kJsonChunk, json, ' ');
  if (has_bin) put_chunk(out, kBinChunk, bin, '\0');
  out.append(rest);
  unsigned char length[4];
  store_le(length, static_cast<std::uint32_t>(out.size()));
  out.replace(8, 4, reinterpret_cast<const char*>(length), 4);
  return out;
}

std::string base64_encode(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k)
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kBase64[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return out;
}

std::optional<std::string> base64_decode(std::string_view text) {
  while (!text.empty() && text.back() == '=') text.remove_suffix(1);
  std::string out;
  out.reserve(text.size() / 4 * 3 + 3);
  std::uint32_t v = 0;
  int bits = 0;
  for (const char c : text) {
    const int d = base64_value(c);
    if (d < 0) return std::nullopt;
    v = (v << 6) | static_cast<std::uint32_t>(d);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((v >> bits) & 0xff);
    }
  }
  return out;
}

std::optional<DataUri> decode_data_uri(std::string_view uri, std::string& error) {
  const std::size_t comma = uri.find(',');
  if (comma == std::string_view::npos) {
    error = "malformed data URI (no ',')";
    return std::nullopt;
  }
  const std::string_view header = uri.substr(0, comma);
  DataUri out;
  out.prefix = std::string(uri.substr(0, comma + 1));
  if (header.size() < 7 || header.substr(header.size() - 7) != ";base64") {
    error = "data URI is not base64";  // glTF writers only use base64
    return std::nullopt;
  }
  std::optional<std::string> bytes = base64_decode(uri.substr(comma + 1));
  if (!bytes) {
    error = "data URI has a character outside base64";
    return std::nullopt;
  }
  out.bytes = std::move(*bytes);
  return out;
}

bool uri_decode(std::string_view uri, std::string& out) {
  out.clear();
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      out += uri[i];
      continue;
    }
    if (i + 2 >= uri.size()) return false;
    const int hi = hex_value(uri[i + 1]), lo = hex_value(uri[i + 2]);
    if (hi < 0 || lo < 0) return false;
    out += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  return out.find('\0') == std::string::npos;
}

std::string uri_encode(std::string_view name) {
  std::string out;
  for (const char ch : name) {
    const auto c = static_cast<unsigned char>(ch);
    const bool unreserved = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                            c == '-' || c == '.' || c == '_' || c == '~';
    if (unreserved) {
      out += ch;
      continue;
    }
    constexpr char kHex[] = "0123456789ABCDEF";
    out += '%';
    out += kHex[c >> 4];
    out += kHex[c & 15];
  }
  return out;
}

bool is_remote_or_absolute(std::string_view uri) {
  if (!uri.empty() && (uri[0] == '/' || uri[0] == '\\')) return true;
  // A scheme: letters, digits, '+', '-', '.' before the first ':' (and before any '/').
  const std::size_t colon = uri.find(':');
  if (colon == std::string_view::npos || colon == 0) return false;
  for (std::size_t i = 0; i < colon; ++i) {
    const char c = uri[i];
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (i > 0 && ((c >= '0' && c <= '9') || c == '+' || c == '-' || c == '.'));
    if (!ok) return false;
  }
  return true;
}

std::size_t json_depth(std::string_view text) {
  std::size_t depth = 0, deepest = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;  // the escaped character cannot end the string
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return deepest;
}

std::string dump_like(const Json& j, std::string_view original) {
  const std::size_t newline = original.find('\n');
  const bool final_newline = !original.empty() && original.back() == '\n';
  std::string text;
  if (newline == std::string_view::npos || newline + 1 >= original.size()) {
    text = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  } else {
    const char c = original[newline + 1] == '\t' ? '\t' : ' ';
    std::size_t width = 0;
    while (newline + 1 + width < original.size() && original[newline + 1 + width] == c) ++width;
    text = j.dump(static_cast<int>(width == 0 ? 2 : width), c, false, Json::error_handler_t::replace);
  }
  if (final_newline) text += '\n';
  return text;
}

}  // namespace freeform::gltf_detail
