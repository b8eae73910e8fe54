// The PLY header parser and the values of the PLY scalar types (ply_header.h).
#include "freeform/io/ply_header.h"

#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

namespace freeform::ply_detail {
namespace {

using io_detail::fail;
using io_detail::quote;

// The encoding named on a 'format' line.
Encoding parse_format(io_detail::Tokens& t, const io_detail::LineReader& lines) {
  std::string_view a;
  if (!t.next(a)) lines.fail("format line without an encoding");
  if (a == "ascii") return Encoding::Ascii;
  if (a == "binary_little_endian") return Encoding::BinaryLittle;
  if (a == "binary_big_endian") return Encoding::BinaryBig;
  lines.fail(
      fmt::format("unknown PLY format {} (expected ascii, binary_little_endian or binary_big_endian)", quote(a)));
}

// The rest of a 'property' line: "type name" or "list count_type item_type name".
Property parse_property(io_detail::Tokens& t, const io_detail::LineReader& lines) {
  Property p;
  std::string_view a;
  std::string_view b;
  if (!t.next(a)) lines.fail("property line without a type");
  if (a == "list") {
    std::string_view c;
    if (!t.next(b) || !t.next(c)) lines.fail("list property needs a count type and an item type");
    const auto ct = parse_scalar(b);
    const auto it = parse_scalar(c);
    if (!ct) lines.fail(fmt::format("unknown PLY type {}", quote(b)));
    if (!it) lines.fail(fmt::format("unknown PLY type {}", quote(c)));
    if (!is_integer(*ct)) lines.fail(fmt::format("list count type {} must be an integer type", quote(b)));
    p.is_list = true;
    p.count_type = *ct;
    p.type = *it;
  } else {
    const auto st = parse_scalar(a);
    if (!st) lines.fail(fmt::format("unknown PLY type {}", quote(a)));
    p.type = *st;
  }
  std::string_view pname;
  if (!t.next(pname)) lines.fail("property without a name");
  p.name = std::string(pname);
  return p;
}

// Other writers put free text in the header without 'comment' (Blender 2.47: "Created by
// Blender3D ..."); other readers skip such lines, so do we, and say so.
void skip_unknown_line(std::string_view line, const io_detail::LineReader& lines, Header& header,
                       std::vector<std::string>& warnings) {
  const std::string text = quote(line.substr(0, std::min<std::size_t>(line.size(), 60)));
  warnings.push_back(
      fmt::format("{}:{}: unknown PLY header line {} read as a comment", lines.name(), lines.line_number(), text));
  if (header.skipped.empty()) header.skipped = fmt::format("line {} {}", lines.line_number(), text);
  header.has_comments = true;
}

// Calls f(T{}) with the C++ type of a PLY scalar type.
template <class F>
auto with_scalar_type(Scalar t, F&& f) {
  switch (t) {
    case Scalar::I8: return f(std::int8_t{});
    case Scalar::U8: return f(std::uint8_t{});
    case Scalar::I16: return f(std::int16_t{});
    case Scalar::U16: return f(std::uint16_t{});
    case Scalar::I32: return f(std::int32_t{});
    case Scalar::U32: return f(std::uint32_t{});
    case Scalar::F32: return f(float{});
    case Scalar::F64: break;
  }
  return f(double{});
}

}  // namespace

std::optional<Scalar> parse_scalar(std::string_view s) {
  if (s == "char" || s == "int8") return Scalar::I8;
  if (s == "uchar" || s == "uint8") return Scalar::U8;
  if (s == "short" || s == "int16") return Scalar::I16;
  if (s == "ushort" || s == "uint16") return Scalar::U16;
  if (s == "int" || s == "int32") return Scalar::I32;
  if (s == "uint" || s == "uint32") return Scalar::U32;
  if (s == "float" || s == "float32") return Scalar::F32;
  if (s == "double" || s == "float64") return Scalar::F64;
  return std::nullopt;
}

std::size_t scalar_size(Scalar t) {
  switch (t) {
    case Scalar::I8:
    case Scalar::U8:
      return 1;
    case Scalar::I16:
    case Scalar::U16:
      return 2;
    case Scalar::I32:
    case Scalar::U32:
    case Scalar::F32:
      return 4;
    case Scalar::F64:
      return 8;
  }
  return 1;
}

double integer_max(Scalar t) {
  switch (t) {
    case Scalar::I8: return 127;
    case Scalar::U8: return 255;
    case Scalar::I16: return 32767;
    case Scalar::U16: return 65535;
    case Scalar::I32: return 2147483647.0;
    case Scalar::U32: return 4294967295.0;
    case Scalar::F32:
    case Scalar::F64: break;
  }
  return 1;
}

Header parse_header(std::string_view data, const std::string& name, std::vector<std::string>& warnings) {
  io_detail::LineReader lines(data, name);
  std::string_view line;
  if (!lines.next(line)) fail(name, 0, "empty file");
  {
    io_detail::Tokens t(line);
    std::string_view magic;
    if (!t.next(magic) || magic != "ply" || !t.at_end()) lines.fail("not a PLY file (first line must be 'ply')");
  }
  Header header;
  bool have_format = false;
  while (lines.next(line)) {
    io_detail::Tokens t(line);
    std::string_view kw;
    if (!t.next(kw)) continue;
    if (kw == "comment" || kw == "obj_info") {
      header.has_comments = true;
    } else if (kw == "end_header") {
      if (!have_format) lines.fail("missing 'format' line in the PLY header");
      header.body_offset = lines.offset();
      header.body_line = lines.line_number() + 1;
      return header;
    } else if (kw == "format") {
      header.encoding = parse_format(t, lines);
      have_format = true;
    } else if (kw == "element") {
      std::string_view a;
      std::string_view b;
      if (!t.next(a) || !t.next(b)) lines.fail("element line needs a name and a count");
      Element e;
      e.name = std::string(a);
      if (!io_detail::parse_int(b, e.count)) lines.fail(fmt::format("invalid element count {}", quote(b)));
      header.elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (header.elements.empty()) lines.fail("property before any element");
      header.elements.back().props.push_back(parse_property(t, lines));
    } else {
      skip_unknown_line(line, lines, header, warnings);
    }
  }
  fail(name, lines.line_number(),
       "unexpected end of file: PLY header has no 'end_header' line" + header.skipped_hint());
}

// ---- values in a property's type ---------------------------------------------------------------

double load_double(Scalar t, const unsigned char* p, bool swap) {
  return with_scalar_type(t, [&](auto tag) { return static_cast<double>(load<decltype(tag)>(p, swap)); });
}

std::int64_t load_int(Scalar t, const unsigned char* p, bool swap) {
  return with_scalar_type(t, [&](auto tag) -> std::int64_t {
    using T = decltype(tag);
    if constexpr (std::is_floating_point_v<T>) return 0;  // excluded by the header checks
    else return static_cast<std::int64_t>(load<T>(p, swap));
  });
}

double to_type(Scalar t, double value) {
  return with_scalar_type(t, [&](auto tag) -> double {
    using T = decltype(tag);
    if constexpr (std::is_floating_point_v<T>) {
      return static_cast<double>(static_cast<T>(value));
    } else {
      if (std::isnan(value)) return 0;
      return std::clamp(std::round(value), static_cast<double>(std::numeric_limits<T>::min()),
                        static_cast<double>(std::numeric_limits<T>::max()));
    }
  });
}

void store_value(Scalar t, double value, unsigned char* p, bool swap) {
  with_scalar_type(t, [&](auto tag) {
    using T = decltype(tag);
    store<T>(p, static_cast<T>(to_type(t, value)), swap);
  });
}

void append_binary(std::string& out, Scalar t, double value) {
  const std::size_t at = out.size();
  out.resize(at + scalar_size(t));
  store_value(t, value, reinterpret_cast<unsigned char*>(out.data() + at), std::endian::native == std::endian::big);
}

void append_value(std::string& out, Scalar t, double value) {
  const double v = to_type(t, value);
  if (t == Scalar::F32)
    io_detail::append_number(out, static_cast<float>(v));
  else if (t == Scalar::F64)
    io_detail::append_number(out, v);
  else
    io_detail::append_number(out, static_cast<std::int64_t>(v));
}

bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

}  // namespace freeform::ply_detail
