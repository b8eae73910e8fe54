// Stanford PLY: ascii, binary_little_endian and binary_big_endian. Reads the vertex element's
// x, y, z (any scalar type) and the face element's vertex_indices / vertex_index list (any
// integer types); every other property and element is skipped.
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <optional>
#include <utility>

namespace freeform {
namespace {

using io_detail::fail;
using io_detail::quote;

enum class Scalar : std::uint8_t { I8, U8, I16, U16, I32, U32, F32, F64 };
enum class Encoding { Ascii, BinaryLittle, BinaryBig };

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

bool is_integer(Scalar t) { return t != Scalar::F32 && t != Scalar::F64; }

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
    for (const Property& p : props)
      if (p.is_list) return true;
    return false;
  }
};

struct Header {
  Encoding encoding = Encoding::Ascii;
  std::vector<Element> elements;
  std::size_t body_offset = 0;
  std::size_t body_line = 0;  // 1-based line of the first body byte (ascii)
  std::string skipped;        // the first unknown header line read as a comment ("line N 'text'")
};

// What the reader extracts: property roles inside the vertex and face elements.
enum class Role : std::uint8_t { Skip, X, Y, Z, Indices };

struct Layout {
  std::size_t vertex_element = 0;
  std::size_t face_element = 0;
  std::uint64_t vertex_count = 0;
  std::vector<std::vector<Role>> roles;  // per element, per property
};

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
    if (kw == "comment" || kw == "obj_info") continue;
    if (kw == "end_header") {
      if (!have_format) lines.fail("missing 'format' line in the PLY header");
      header.body_offset = lines.offset();
      header.body_line = lines.line_number() + 1;
      return header;
    }
    std::string_view a;
    std::string_view b;
    if (kw == "format") {
      if (!t.next(a)) lines.fail("format line without an encoding");
      if (a == "ascii")
        header.encoding = Encoding::Ascii;
      else if (a == "binary_little_endian")
        header.encoding = Encoding::BinaryLittle;
      else if (a == "binary_big_endian")
        header.encoding = Encoding::BinaryBig;
      else
        lines.fail(
            fmt::format("unknown PLY format {} (expected ascii, binary_little_endian or binary_big_endian)", quote(a)));
      have_format = true;
    } else if (kw == "element") {
      if (!t.next(a) || !t.next(b)) lines.fail("element line needs a name and a count");
      Element e;
      e.name = std::string(a);
      if (!io_detail::parse_int(b, e.count)) lines.fail(fmt::format("invalid element count {}", quote(b)));
      header.elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (header.elements.empty()) lines.fail("property before any element");
      Property p;
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
      header.elements.back().props.push_back(std::move(p));
    } else {
      // Other writers put free text here without 'comment' (Blender 2.47: "Created by Blender3D
      // ..."); other readers skip such lines, so do we, and say so.
      const std::string text = quote(line.substr(0, std::min<std::size_t>(line.size(), 60)));
      warnings.push_back(fmt::format("{}:{}: unknown PLY header line {} read as a comment", name, lines.line_number(), text));
      if (header.skipped.empty()) header.skipped = fmt::format("line {} {}", lines.line_number(), text);
    }
  }
  fail(name, lines.line_number(),
       "unexpected end of file: PLY header has no 'end_header' line" +
           (header.skipped.empty() ? std::string() : " (" + header.skipped + " was not understood)"));
}

Layout make_layout(const Header& header, const std::string& name) {
  Layout layout;
  std::optional<std::size_t> vertex;
  std::optional<std::size_t> face;
  layout.roles.resize(header.elements.size());
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& el = header.elements[e];
    layout.roles[e].assign(el.props.size(), Role::Skip);
    if (el.name == "vertex") {
      if (vertex) fail(name, 0, "PLY header has more than one 'vertex' element");
      vertex = e;
    } else if (el.name == "face") {
      if (face) fail(name, 0, "PLY header has more than one 'face' element");
      face = e;
    }
  }
  const std::string hint = header.skipped.empty() ? "" : " (" + header.skipped + " was not understood)";
  if (!vertex) fail(name, 0, "PLY header has no 'vertex' element" + hint);
  if (!face) fail(name, 0, "no faces (PLY header has no 'face' element)" + hint);
  layout.vertex_element = *vertex;
  layout.face_element = *face;

  const Element& v = header.elements[*vertex];
  const char* axes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    bool found = false;
    for (std::size_t p = 0; p < v.props.size(); ++p) {
      if (v.props[p].name != axes[k]) continue;
      if (v.props[p].is_list) fail(name, 0, fmt::format("vertex property '{}' is a list, expected a scalar", axes[k]));
      if (found) fail(name, 0, fmt::format("vertex element has two '{}' properties", axes[k]));
      layout.roles[*vertex][p] = static_cast<Role>(static_cast<int>(Role::X) + k);
      found = true;
    }
    if (!found) fail(name, 0, fmt::format("vertex element has no '{}' property", axes[k]));
  }
  const Element& f = header.elements[*face];
  bool found = false;
  for (std::size_t p = 0; p < f.props.size(); ++p) {
    if (f.props[p].name != "vertex_indices" && f.props[p].name != "vertex_index") continue;
    if (found) fail(name, 0, "face element has both 'vertex_indices' and 'vertex_index'");
    if (!f.props[p].is_list) fail(name, 0, fmt::format("face property '{}' must be a list", f.props[p].name));
    if (!is_integer(f.props[p].type))
      fail(name, 0, fmt::format("face property '{}' must have an integer item type", f.props[p].name));
    layout.roles[*face][p] = Role::Indices;
    found = true;
  }
  if (!found) fail(name, 0, "face element has no 'vertex_indices' (or 'vertex_index') list property");

  layout.vertex_count = v.count;
  if (v.count == 0) fail(name, 0, "no vertices (vertex element count is 0)");
  if (f.count == 0) fail(name, 0, "no faces (face element count is 0)");
  if (v.count > io_detail::kMaxElements) fail(name, 0, fmt::format("vertex count {} is too large", v.count));
  if (f.count > io_detail::kMaxElements) fail(name, 0, fmt::format("face count {} is too large", f.count));
  return layout;
}

// ---- binary ----------------------------------------------------------------------------------

template <class T>
T load(const unsigned char* p, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, p, sizeof(T));
  if (swap) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
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

class BinaryBody {
 public:
  BinaryBody(std::string_view body, bool swap, const std::string& name)
      : p_(reinterpret_cast<const unsigned char*>(body.data())), size_(body.size()), swap_(swap), name_(name) {}

  void read(const Header& header, const Layout& layout, TriangleSoup& soup, io_detail::FanCounter& fan) {
    check_total_size(header);
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
      const Element& el = header.elements[e];
      if (el.props.empty()) continue;  // zero bytes per entry
      const std::size_t min_size = el.min_binary_size();
      const std::size_t remaining = size_ - pos_;
      if (el.count > remaining / min_size)
        fail(name_, 0,
             fmt::format("file truncated: element '{}' declares {} entries but the remaining {} bytes hold at most {}",
                         el.name, el.count, remaining, remaining / min_size));
      const std::vector<Role>& roles = layout.roles[e];
      if (e == layout.vertex_element) soup.positions.reserve(el.count);
      if (e == layout.face_element) soup.faces.reserve(el.count);
      if (e != layout.vertex_element && e != layout.face_element && !el.has_lists()) {
        pos_ += el.count * min_size;  // fits: checked above
        continue;
      }
      for (std::uint64_t i = 0; i < el.count; ++i) read_entry(el, roles, i, layout.vertex_count, soup, fan);
    }
  }

  std::size_t trailing() const { return size_ - pos_; }

 private:
  // Before reading anything: the declared counts times the smallest entry sizes must fit in the
  // body (catches "fewer entries than the header says" and absurd counts up front).
  void check_total_size(const Header& header) const {
    std::uint64_t needed = 0;
    std::string detail;
    bool overflow = false;
    for (const Element& el : header.elements) {
      const std::size_t min_size = el.min_binary_size();
      if (min_size == 0 || el.count == 0) continue;
      if (!detail.empty()) detail += ", ";
      detail += fmt::format("{}: {} x {}", el.name, el.count, min_size);
      if (el.count > (size_ - needed) / min_size) overflow = true;
      if (!overflow) needed += el.count * min_size;
    }
    if (overflow)
      fail(name_, 0,
           fmt::format("file truncated: the header declares more data than the {} bytes after it (entries x minimum "
                       "bytes: {})",
                       size_, detail));
  }

  void need(std::size_t bytes, const Element& el, std::uint64_t i) const {
    if (bytes > size_ - pos_) fail(name_, 0, fmt::format("file truncated in {} {}", el.name, i));
  }

  void read_entry(const Element& el, const std::vector<Role>& roles, std::uint64_t i, std::uint64_t nv,
                  TriangleSoup& soup, io_detail::FanCounter& fan) {
    double xyz[3] = {0, 0, 0};
    bool is_vertex = false;
    for (std::size_t k = 0; k < el.props.size(); ++k) {
      const Property& prop = el.props[k];
      if (!prop.is_list) {
        const std::size_t s = scalar_size(prop.type);
        need(s, el, i);
        if (roles[k] != Role::Skip) {
          is_vertex = true;
          const double value = load_double(prop.type, p_ + pos_, swap_);
          if (!std::isfinite(value)) fail(name_, 0, fmt::format("vertex {} has a non-finite coordinate", i));
          xyz[static_cast<int>(roles[k]) - static_cast<int>(Role::X)] = value;
        }
        pos_ += s;
        continue;
      }
      const std::size_t cs = scalar_size(prop.count_type);
      need(cs, el, i);
      const std::int64_t count = load_int(prop.count_type, p_ + pos_, swap_);
      pos_ += cs;
      if (count < 0) fail(name_, 0, fmt::format("{} {}: negative list length {}", el.name, i, count));
      const std::size_t is = scalar_size(prop.type);
      if (static_cast<std::uint64_t>(count) > (size_ - pos_) / is)
        fail(name_, 0, fmt::format("file truncated in {} {} (list of {} entries)", el.name, i, count));
      if (roles[k] == Role::Indices) {
        if (count < 3) fail(name_, 0, fmt::format("face {} has {} vertices (at least 3 needed)", i, count));
        poly_.clear();
        for (std::int64_t j = 0; j < count; ++j) {
          const std::int64_t index = load_int(prop.type, p_ + pos_, swap_);
          pos_ += is;
          if (index < 0 || static_cast<std::uint64_t>(index) >= nv)
            fail(name_, 0, fmt::format("face {}: vertex index {} out of range (file has {} vertices)", i, index, nv));
          poly_.push_back(static_cast<int>(index));
        }
        fan.add(poly_, soup.faces);
      } else {
        pos_ += static_cast<std::size_t>(count) * is;
      }
    }
    if (is_vertex) soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  const unsigned char* p_;
  std::size_t size_;
  std::size_t pos_ = 0;
  bool swap_;
  const std::string& name_;
  std::vector<int> poly_;
};

// ---- ascii -----------------------------------------------------------------------------------

void read_ascii_body(io_detail::TokenReader& tokens, const Header& header, const Layout& layout, TriangleSoup& soup,
                     io_detail::FanCounter& fan) {
  std::vector<int> poly;
  const std::uint64_t nv = layout.vertex_count;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& el = header.elements[e];
    if (el.props.empty()) continue;
    const std::vector<Role>& roles = layout.roles[e];
    const bool is_vertex = e == layout.vertex_element;
    if (is_vertex) soup.positions.reserve(io_detail::capped_reserve(el.count, tokens.remaining(), 2 * el.props.size()));
    if (e == layout.face_element) soup.faces.reserve(io_detail::capped_reserve(el.count, tokens.remaining(), 8));
    const std::string what = "a value of element '" + el.name + "'";
    for (std::uint64_t i = 0; i < el.count; ++i) {
      double xyz[3] = {0, 0, 0};
      for (std::size_t k = 0; k < el.props.size(); ++k) {
        const Property& prop = el.props[k];
        std::string_view tok = tokens.require(what.c_str());
        if (!prop.is_list) {
          if (roles[k] != Role::Skip) {
            double& c = xyz[static_cast<int>(roles[k]) - static_cast<int>(Role::X)];
            if (!io_detail::parse_double(tok, c))
              tokens.fail(fmt::format("vertex {}: invalid coordinate {}", i, quote(tok)));
            if (!std::isfinite(c)) tokens.fail(fmt::format("vertex {} has a non-finite coordinate {}", i, quote(tok)));
          }
          continue;
        }
        std::int64_t count = 0;
        if (!io_detail::parse_int(tok, count) || count < 0)
          tokens.fail(fmt::format("{} {}: invalid list length {}", el.name, i, quote(tok)));
        if (roles[k] == Role::Indices) {
          if (count < 3) tokens.fail(fmt::format("face {} has {} vertices (at least 3 needed)", i, count));
          poly.clear();
          for (std::int64_t j = 0; j < count; ++j) {
            tok = tokens.require("a vertex index");
            std::int64_t index = 0;
            if (!io_detail::parse_int(tok, index))
              tokens.fail(fmt::format("face {}: invalid vertex index {}", i, quote(tok)));
            if (index < 0 || static_cast<std::uint64_t>(index) >= nv)
              tokens.fail(fmt::format("face {}: vertex index {} out of range (file has {} vertices)", i, index, nv));
            poly.push_back(static_cast<int>(index));
          }
          fan.add(poly, soup.faces);
        } else {
          for (std::int64_t j = 0; j < count; ++j) tokens.require(what.c_str());
        }
      }
      if (is_vertex) soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
    }
  }
}

template <class T>
void append_le(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

}  // namespace

TriangleSoup read_ply(std::string_view data, const std::string& name, std::vector<std::string>& warnings) {
  if (data.empty()) fail(name, 0, "empty file");
  const Header header = parse_header(data, name, warnings);
  const Layout layout = make_layout(header, name);
  TriangleSoup soup;
  io_detail::FanCounter fan;
  const std::string_view body = data.substr(header.body_offset);
  if (header.encoding == Encoding::Ascii) {
    io_detail::TokenReader tokens(body, header.body_line, name);
    read_ascii_body(tokens, header, layout, soup, fan);
    std::string_view extra;
    if (tokens.next(extra))
      warnings.push_back(fmt::format("{}:{}: data after the last element ignored", name, tokens.line_number()));
  } else {
    const bool file_big = header.encoding == Encoding::BinaryBig;
    const bool swap = file_big != (std::endian::native == std::endian::big);
    BinaryBody reader(body, swap, name);
    reader.read(header, layout, soup, fan);
    if (reader.trailing() > 0)
      warnings.push_back(fmt::format("{}: {} bytes after the last element ignored", name, reader.trailing()));
  }
  io_detail::require_nonempty(soup, name);
  fan.warn(warnings);
  return soup;
}

std::string write_ply(const TriangleSoup& soup, bool binary) {
  io_detail::check_soup_for_writing(soup);
  std::string out = fmt::format(
      "ply\nformat {} 1.0\ncomment written by freeform\nelement vertex {}\nproperty double x\nproperty double y\n"
      "property double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      binary ? "binary_little_endian" : "ascii", soup.positions.size(), soup.faces.size());
  if (binary) {
    out.reserve(out.size() + soup.positions.size() * 24 + soup.faces.size() * 13);
    for (const Vec3& p : soup.positions)
      for (int k = 0; k < 3; ++k) append_le<double>(out, p[k]);
    for (const Tri& f : soup.faces) {
      out += static_cast<char>(3);
      for (int v : f) append_le<std::int32_t>(out, v);
    }
    return out;
  }
  out.reserve(out.size() + soup.positions.size() * 64 + soup.faces.size() * 32);
  io_detail::append_ascii_vertices_and_faces(out, soup);
  return out;
}

}  // namespace freeform
