// Internal: the model of a PLY header (scalar types, properties, elements, encodings), its
// parser and the reading and writing of one value in a property's type, shared by the reader
// (ply.cpp, ply_layout.cpp), the rewrite (ply_rewrite.cpp) and the writer (ply_write.cpp).
// Not part of the public API.
#pragma once

#include "freeform/common/huge_pages.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace freeform::ply_detail {

enum class Scalar : std::uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class Encoding { Ascii, BinaryLittle, BinaryBig };

// "char" / "int8" ... "double" / "float64"; nullopt for anything else.
std::optional<Scalar> parse_scalar(std::string_view s);
std::size_t scalar_size(Scalar t);
inline bool is_integer(Scalar t) { return t != Scalar::F32 && t != Scalar::F64; }
// The largest value of an integer type (colours are stored as value / maximum); 1 for floats.
double integer_max(Scalar t);

struct Property {
  std::string name;
  bool is_list = false;
  Scalar count_type = Scalar::U8;  // lists only
  Scalar type = Scalar::F32;       // scalar type, or list item type
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  // Bytes of one entry when every list is empty (binary), used to reject impossible counts.
  std::size_t min_binary_size() const {
    std::size_t s = 0;
    for (const Property& p : props) s += scalar_size(p.is_list ? p.count_type : p.type);
    return s;
  }
  bool has_lists() const {
    return std::any_of(props.begin(), props.end(), [](const Property& p) { return p.is_list; });
  }
};

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  std::size_t body_offset = 0;
  std::size_t body_line = 0;  // 1-based line of the first body byte (ascii)
  std::string skipped;        // the first unknown header line read as a comment ("line N 'text'")
  bool has_comments = false;  // comment, obj_info or unknown lines
  // " (line N 'text' was not understood)" after an error message, or "".
  std::string skipped_hint() const { return skipped.empty() ? "" : " (" + skipped + " was not understood)"; }
};

// The header of `data`; unknown lines are read as comments with a warning. Throws IoError.
Header parse_header(std::string_view data, const std::string& name, std::vector<std::string>& warnings);

// Whether binary values of a file in `encoding` must be byte swapped on this machine.
inline bool needs_swap(Encoding encoding) {
  return (encoding == Encoding::BinaryBig) != (std::endian::native == std::endian::big);
}

// Property names readers give a meaning to: positions, normals, texture coordinates, colours.
inline constexpr std::array<std::string_view, 3> kPositionNames = {"x", "y", "z"};
inline constexpr std::array<std::string_view, 3> kNormalNames = {"nx", "ny", "nz"};
inline constexpr std::array<std::array<std::string_view, 2>, 4> kUvNames = {
    {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}}};
inline constexpr std::array<std::array<std::string_view, 4>, 2> kColorNames = {
    {{"red", "green", "blue", "alpha"}, {"diffuse_red", "diffuse_green", "diffuse_blue", "diffuse_alpha"}}};

// ---- values in a property's type ---------------------------------------------------------------

template <class T>
T load(const unsigned char* p, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

template <class T>
void store(unsigned char* p, T value, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (swap) std::reverse(bytes, bytes + sizeof(T));
  std::memcpy(p, bytes, sizeof(T));
}

// `value` appended in little-endian byte order.
template <class T>
void append_le(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  store<T>(bytes, value, std::endian::native == std::endian::big);
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

double load_double(Scalar t, const unsigned char* p, bool swap);
std::int64_t load_int(Scalar t, const unsigned char* p, bool swap);  // integer types only (0 for floats)

// `value` as a property of type t holds it: floats rounded to the type, integers rounded and
// clamped to its range (NaN becomes 0).
double to_type(Scalar t, double value);

// to_type(t, value) written at p in type t.
void store_value(Scalar t, double value, unsigned char* p, bool swap);
// to_type(t, value) appended in type t, little endian.
void append_binary(std::string& out, Scalar t, double value);
// Shortest decimal that reads back to the value in the property's type.
void append_value(std::string& out, Scalar t, double value);

// Whether a rewrite keeps a value as the file has it (NaN payloads included).
bool same_value(double a, double b);

// Large arrays cost mostly their first-touch page faults: huge pages cut those (huge_pages.h).
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

inline void reserve_huge(std::string& s, std::size_t n) {
  s.reserve(n);
  advise_huge_pages(s.data(), s.capacity());
}

}  // namespace freeform::ply_detail
