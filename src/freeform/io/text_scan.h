// Internal helpers shared by the format readers and writers: line and token scanning over an
// in-memory buffer (no allocation per line), number parsing with std::from_chars, error
// helpers and fan triangulation. Not part of the public API.
#pragma once

#include "freeform/common/error.h"
#include "freeform/io/mesh_attributes.h"
#include "freeform/mesh/types.h"

#include <charconv>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace freeform::io_detail {

// Throws IoError(name, line, message); line 0 means "no line" (binary data, whole file).
[[noreturn]] void fail(const std::string& name, std::size_t line, const std::string& message);

// A short printable rendering of a token for error messages: quoted, at most ~24 characters,
// non-printable bytes shown as '?'.
std::string quote(std::string_view token);

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Bytes that never occur in a text mesh file: NUL and control characters other than
// tab, LF, CR, VT, FF; and DEL.
inline bool is_binary_byte(char ch) {
  const auto c = static_cast<unsigned char>(ch);
  return (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f') || c == 0x7f;
}

// Splits a text buffer into lines ('\n', with an optional '\r' before it), counting 1-based line
// numbers. A UTF-8 byte order mark at the start is skipped. A line containing binary bytes is an
// IoError "binary data at line N".
class LineReader {
 public:
  LineReader(std::string_view data, const std::string& name);
  // The next line without its terminator; false at the end of the data.
  bool next(std::string_view& line);
  std::size_t line_number() const { return line_; }  // of the line last returned
  std::size_t offset() const { return pos_; }        // first byte after the line last returned
  std::size_t remaining() const { return data_.size() - pos_; }
  const std::string& name() const { return name_; }
  [[noreturn]] void fail(const std::string& message) const { io_detail::fail(name_, line_, message); }

 private:
  std::string_view data_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::size_t line_ = 0;
};

// Whitespace-separated tokens of one line.
class Tokens {
 public:
  explicit Tokens(std::string_view line) : p_(line.data()), end_(line.data() + line.size()) {}
  bool next(std::string_view& token) {
    while (p_ != end_ && is_space(*p_)) ++p_;
    if (p_ == end_) return false;
    const char* start = p_;
    while (p_ != end_ && !is_space(*p_)) ++p_;
    token = std::string_view(start, static_cast<std::size_t>(p_ - start));
    return true;
  }
  bool at_end() {
    while (p_ != end_ && is_space(*p_)) ++p_;
    return p_ == end_;
  }
  std::string_view rest() const { return std::string_view(p_, static_cast<std::size_t>(end_ - p_)); }

 private:
  const char* p_;
  const char* end_;
};

// Whitespace-separated tokens across lines (PLY ascii bodies, ascii STL), with line numbers and
// binary detection.
class TokenReader {
 public:
  TokenReader(std::string_view data, std::size_t first_line, const std::string& name)
      : data_(data), name_(name), line_(first_line), token_line_(first_line) {}
  // The next token; false at the end of the data.
  bool next(std::string_view& token);
  // Skips the rest of the current line (after the last token returned).
  void skip_line();
  std::size_t line_number() const { return token_line_; }  // of the token last returned
  std::size_t remaining() const { return data_.size() - pos_; }
  [[noreturn]] void fail(const std::string& message) const { io_detail::fail(name_, token_line_, message); }
  // Next token or IoError "unexpected end of file (expected <what>)".
  std::string_view require(const char* what);

 private:
  std::string_view data_;
  const std::string& name_;
  std::size_t pos_ = 0;
  std::size_t line_;
  std::size_t token_line_;
};

// Whole-token parse of a number with std::from_chars (a leading '+' is accepted); false on
// trailing characters or overflow. For floating point, NaN and infinities parse successfully:
// callers check finiteness to name the vertex.
template <class Number>
bool parse_number(std::string_view token, Number& out) {
  const char* first = token.data();
  const char* last = token.data() + token.size();
  if (first != last && *first == '+') {
    ++first;
    if (first != last && (*first == '-' || *first == '+')) return false;
  }
  if (first == last) return false;
  auto [ptr, ec] = std::from_chars(first, last, out);
  return ec == std::errc() && ptr == last;
}
template <class Real>
bool parse_real(std::string_view token, Real& out) {
  return parse_number(token, out);
}
inline bool parse_double(std::string_view token, double& out) { return parse_number(token, out); }
template <class Int>
bool parse_int(std::string_view token, Int& out) {
  return parse_number(token, out);
}

// min(count, max_by_bytes): how many elements to reserve so a lying header cannot trigger a huge
// allocation before the data is seen.
inline std::size_t capped_reserve(std::uint64_t count, std::size_t remaining_bytes, std::size_t min_bytes_each) {
  const std::uint64_t by_bytes = remaining_bytes / (min_bytes_each == 0 ? 1 : min_bytes_each) + 1;
  return static_cast<std::size_t>(count < by_bytes ? count : by_bytes);
}

// Largest vertex / face count a soup can index (faces use int indices).
inline constexpr std::uint64_t kMaxElements = 0x7fffffff;

// Fan-triangulates polygon `poly` (at least 3 indices) into `faces`; counts polygons with more
// than three corners in `polygons` and the triangles they produced in `triangles`. With
// `attributes`, the polygon itself is kept there too (Polygons, triangle_polygon).
struct FanCounter {
  std::size_t polygons = 0;
  std::size_t triangles = 0;
  std::size_t stripped = 0;  // large convex polygons cut into strips (triangulate.h)
  std::size_t clipped = 0;   // non-convex polygons cut by ear clipping
  // Triangulates poly (corners into `positions`, the vertices read so far) into faces.
  void add(const std::vector<int>& poly, std::span<const Vec3> positions, std::vector<Tri>& faces,
           MeshAttributes* attributes = nullptr);
  // Appends the summary warning if any polygon was split.
  void warn(std::vector<std::string>& warnings) const;
};

// Throws IoError when the soup has no vertices or no faces.
void require_nonempty(const TriangleSoup& soup, const std::string& name);

// Throws InvalidInput when a face index is out of range (writers).
void check_soup_for_writing(const TriangleSoup& soup);

// Appends the shortest round-trip decimal representation.
void append_number(std::string& out, double value);
void append_number(std::string& out, float value);
void append_number(std::string& out, std::int64_t value);

// One "x y z" line per vertex, then one "3 i j k" line per face (the OFF and ascii PLY body).
void append_ascii_vertices_and_faces(std::string& out, const TriangleSoup& soup);

}  // namespace freeform::io_detail
