// Stanford PLY: ascii, binary_little_endian and binary_big_endian. Reads the vertex element's
// x, y, z (any scalar type), the face element's vertex_indices / vertex_index list (any integer
// types) and, as attributes, normals, texture coordinates, colours and every other scalar
// property of those two elements. The FileSource keeps the file: a rewrite changes only the
// x, y, z and nx, ny, nz values, everything else stays byte for byte.
#include "freeform/common/huge_pages.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <set>
#include <type_traits>
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
  bool has_comments = false;  // comment, obj_info or unknown lines
};

// What the reader extracts: property roles inside the vertex and face elements. NX..NZ are
// rewritten with recomputed normals; Attribute values go to Field::target.
enum class Role : std::uint8_t { Skip, X, Y, Z, Indices, NX, NY, NZ, Attribute };

bool is_position(Role r) { return r == Role::X || r == Role::Y || r == Role::Z; }

// Where a scalar property's value goes.
struct Field {
  Role role = Role::Skip;
  int target = -1;  // index into Layout::targets[element] (normals, uv, named attributes)
  int component = 0;
  double scale = 1;  // integer colours: 1 / the type's maximum
};

// One attribute row per entry: `width` values appended to `values` for every entry.
struct Target {
  std::vector<double>* values = nullptr;
  int width = 1;
};

struct Layout {
  std::size_t vertex_element = 0;
  std::size_t face_element = 0;
  std::uint64_t vertex_count = 0;
  std::vector<std::vector<Field>> fields;    // per element, per property
  std::vector<std::vector<Target>> targets;  // per element
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
    if (kw == "comment" || kw == "obj_info") {
      header.has_comments = true;
      continue;
    }
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
      header.has_comments = true;
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
  layout.fields.resize(header.elements.size());
  layout.targets.resize(header.elements.size());
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& el = header.elements[e];
    layout.fields[e].assign(el.props.size(), Field{});
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
      layout.fields[*vertex][p].role = static_cast<Role>(static_cast<int>(Role::X) + k);
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
    layout.fields[*face][p].role = Role::Indices;
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

// ---- attributes ------------------------------------------------------------------------------

// Property names readers give a meaning to: normals, texture coordinates, colours.
constexpr std::array<std::string_view, 3> kNormalNames = {"nx", "ny", "nz"};
constexpr std::array<std::array<std::string_view, 2>, 4> kUvNames = {
    {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"}, {"texture_s", "texture_t"}}};
constexpr std::array<std::array<std::string_view, 4>, 2> kColorNames = {
    {{"red", "green", "blue", "alpha"}, {"diffuse_red", "diffuse_green", "diffuse_blue", "diffuse_alpha"}}};

// The largest value of an integer type (colours are stored as value / maximum).
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

// The first scalar property named `name` that no role claims yet, or -1.
int find_free_scalar(const Element& el, const std::vector<Field>& fields, std::string_view name) {
  for (std::size_t p = 0; p < el.props.size(); ++p)
    if (!el.props[p].is_list && fields[p].role == Role::Skip && el.props[p].name == name) return static_cast<int>(p);
  return -1;
}

enum class Group { Normal, Uv, Color };

// Binds the leading properties of `names` (at least `required` of them, else none) as the
// components of target `target`; returns how many were bound. Normals get the roles NX..NZ.
int bind_group(const Element& el, std::vector<Field>& fields, std::span<const std::string_view> names,
               std::size_t required, Group group, int target) {
  std::array<int, 4> found{};
  std::size_t n = 0;
  for (; n < names.size(); ++n) {
    found[n] = find_free_scalar(el, fields, names[n]);
    if (found[n] < 0) break;
  }
  if (n < required) return 0;
  for (std::size_t k = 0; k < n; ++k) {
    Field& f = fields[static_cast<std::size_t>(found[k])];
    f.role = group == Group::Normal ? static_cast<Role>(static_cast<int>(Role::NX) + static_cast<int>(k)) : Role::Attribute;
    f.target = target;
    f.component = static_cast<int>(k);
    const Scalar type = el.props[static_cast<std::size_t>(found[k])].type;
    if (group == Group::Color && is_integer(type)) f.scale = 1 / integer_max(type);
  }
  return static_cast<int>(n);
}

// The colour and every scalar property no role claims, as named attributes of the element.
void bind_named(const Element& el, std::vector<Field>& fields, std::vector<Target>& targets,
                std::vector<NamedAttribute>& named) {
  const int base = static_cast<int>(targets.size());
  const std::size_t first = named.size();
  for (const auto& names : kColorNames) {
    const int width = bind_group(el, fields, names, 3, Group::Color, base);
    if (width == 0) continue;
    named.push_back({"color", width, {}});
    break;
  }
  for (std::size_t p = 0; p < el.props.size(); ++p) {
    if (el.props[p].is_list || fields[p].role != Role::Skip) continue;
    fields[p] = {Role::Attribute, base + static_cast<int>(named.size() - first), 0, 1};
    named.push_back({el.props[p].name, 1, {}});
  }
  // Pointers are taken once `named` has stopped growing.
  for (std::size_t i = first; i < named.size(); ++i) targets.push_back({&named[i].values, named[i].width});
}

void bind_attributes(const Header& header, Layout& layout, MeshAttributes& attributes) {
  const std::size_t ve = layout.vertex_element;
  const Element& v = header.elements[ve];
  std::vector<Target>& targets = layout.targets[ve];
  if (bind_group(v, layout.fields[ve], kNormalNames, 3, Group::Normal, static_cast<int>(targets.size())) == 3) {
    attributes.normal.width = 3;
    targets.push_back({&attributes.normal.values, 3});
  }
  for (const auto& names : kUvNames) {
    if (bind_group(v, layout.fields[ve], names, 2, Group::Uv, static_cast<int>(targets.size())) == 0) continue;
    attributes.uv.width = 2;
    targets.push_back({&attributes.uv.values, 2});
    break;
  }
  bind_named(v, layout.fields[ve], targets, attributes.vertex);
  const std::size_t fe = layout.face_element;
  bind_named(header.elements[fe], layout.fields[fe], layout.targets[fe], attributes.face);
}

// Appends a row of zeros to each target of an element, filled by set_value.
void begin_entry(const std::vector<Target>& targets) {
  for (const Target& t : targets) t.values->resize(t.values->size() + static_cast<std::size_t>(t.width));
}

void set_value(const std::vector<Target>& targets, const Field& f, double value) {
  const Target& t = targets[static_cast<std::size_t>(f.target)];
  (*t.values)[t.values->size() - static_cast<std::size_t>(t.width - f.component)] = value * f.scale;
}

// Large arrays cost mostly their first-touch page faults: huge pages cut those (huge_pages.h).
template <class T>
void reserve_huge(std::vector<T>& v, std::size_t n) {
  v.reserve(n);
  advise_huge_pages(v.data(), v.capacity() * sizeof(T));
}

void reserve_huge(std::string& s, std::size_t n) {
  s.reserve(n);
  advise_huge_pages(s.data(), s.capacity());
}

void reserve_rows(const std::vector<Target>& targets, std::size_t rows) {
  for (const Target& t : targets) reserve_huge(*t.values, rows * static_cast<std::size_t>(t.width));
}

// Room for `count` triangles (growing these vectors costs more than reading the faces).
void reserve_faces(std::size_t count, ReadResult& out) {
  reserve_huge(out.soup.faces, count);
  reserve_huge(out.attributes.triangle_polygon, count);
  reserve_huge(out.attributes.polygons.offsets, count + 1);
  reserve_huge(out.attributes.polygons.corners, 3 * count);
}

// Keeps a face as a polygon and its fan triangles in the soup.
void add_polygon(const std::vector<int>& poly, ReadResult& out, io_detail::FanCounter& fan) {
  const std::size_t before = out.soup.faces.size();
  fan.add(poly, out.soup.faces);
  MeshAttributes& a = out.attributes;
  a.triangle_polygon.insert(a.triangle_polygon.end(), out.soup.faces.size() - before, a.polygons.size());
  a.polygons.add(poly);
}

// ---- values in a property's type ---------------------------------------------------------------

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

template <class T>
void store(unsigned char* p, T value, bool swap) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (swap) {
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  }
  std::memcpy(p, bytes, sizeof(T));
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

// `value` as a property of type t holds it: floats rounded to the type, integers rounded and
// clamped to its range (NaN becomes 0).
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

// Whether a rewrite keeps a value as the file has it (NaN payloads included).
bool same_value(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// Shortest decimal that reads back to the value in the property's type.
void append_value(std::string& out, Scalar t, double value) {
  const double v = to_type(t, value);
  if (t == Scalar::F32)
    io_detail::append_number(out, static_cast<float>(v));
  else if (t == Scalar::F64)
    io_detail::append_number(out, v);
  else
    io_detail::append_number(out, static_cast<std::int64_t>(v));
}

template <class T>
void append_le(std::string& out, T value) {
  unsigned char bytes[sizeof(T)];
  store<T>(bytes, value, std::endian::native == std::endian::big);
  out.append(reinterpret_cast<const char*>(bytes), sizeof(T));
}

// ---- binary ----------------------------------------------------------------------------------

class BinaryBody {
 public:
  BinaryBody(std::string_view body, bool swap, const std::string& name)
      : p_(reinterpret_cast<const unsigned char*>(body.data())), size_(body.size()), swap_(swap), name_(name) {}

  void read(const Header& header, const Layout& layout, ReadResult& out, io_detail::FanCounter& fan) {
    check_total_size(header);
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
      const Element& el = header.elements[e];
      if (e == layout.vertex_element) vertex_start_ = pos_;
      if (el.props.empty()) continue;  // zero bytes per entry
      const std::size_t min_size = el.min_binary_size();
      const std::size_t remaining = size_ - pos_;
      if (el.count > remaining / min_size)
        fail(name_, 0,
             fmt::format("file truncated: element '{}' declares {} entries but the remaining {} bytes hold at most {}",
                         el.name, el.count, remaining, remaining / min_size));
      const bool is_vertex = e == layout.vertex_element;
      reserve_rows(layout.targets[e], el.count);  // fits: at least one byte per value
      if (is_vertex) reserve_huge(out.soup.positions, el.count);
      if (e == layout.face_element) reserve_faces(el.count, out);
      if (!is_vertex && e != layout.face_element && !el.has_lists()) {
        pos_ += el.count * min_size;  // fits: checked above
        continue;
      }
      for (std::uint64_t i = 0; i < el.count; ++i)
        read_entry(el, layout.fields[e], layout.targets[e], i, is_vertex, layout.vertex_count, out, fan);
    }
  }

  std::size_t trailing() const { return size_ - pos_; }
  std::size_t vertex_start() const { return vertex_start_; }  // body offset of the vertex element

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

  void read_entry(const Element& el, const std::vector<Field>& fields, const std::vector<Target>& targets,
                  std::uint64_t i, bool is_vertex, std::uint64_t nv, ReadResult& out, io_detail::FanCounter& fan) {
    double xyz[3] = {0, 0, 0};
    begin_entry(targets);
    for (std::size_t k = 0; k < el.props.size(); ++k) {
      const Property& prop = el.props[k];
      const Field& field = fields[k];
      if (!prop.is_list) {
        const std::size_t s = scalar_size(prop.type);
        need(s, el, i);
        if (field.role != Role::Skip) {
          const double value = load_double(prop.type, p_ + pos_, swap_);
          if (is_position(field.role)) {
            if (!std::isfinite(value)) fail(name_, 0, fmt::format("vertex {} has a non-finite coordinate", i));
            xyz[static_cast<int>(field.role) - static_cast<int>(Role::X)] = value;
          }
          if (field.target >= 0) set_value(targets, field, value);
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
      if (field.role == Role::Indices) {
        if (count < 3) fail(name_, 0, fmt::format("face {} has {} vertices (at least 3 needed)", i, count));
        poly_.clear();
        for (std::int64_t j = 0; j < count; ++j) {
          const std::int64_t index = load_int(prop.type, p_ + pos_, swap_);
          pos_ += is;
          if (index < 0 || static_cast<std::uint64_t>(index) >= nv)
            fail(name_, 0, fmt::format("face {}: vertex index {} out of range (file has {} vertices)", i, index, nv));
          poly_.push_back(static_cast<int>(index));
        }
        add_polygon(poly_, out, fan);
      } else {
        pos_ += static_cast<std::size_t>(count) * is;
      }
    }
    if (is_vertex) out.soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  const unsigned char* p_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::size_t vertex_start_ = 0;
  bool swap_;
  const std::string& name_;
  std::vector<int> poly_;
};

// ---- ascii -----------------------------------------------------------------------------------

class AsciiBody {
 public:
  AsciiBody(io_detail::TokenReader& tokens, std::size_t body_size, std::uint64_t nv)
      : tokens_(tokens), body_size_(body_size), nv_(nv) {}

  void read(const Header& header, const Layout& layout, ReadResult& out, io_detail::FanCounter& fan) {
    for (std::size_t e = 0; e < header.elements.size(); ++e) {
      const Element& el = header.elements[e];
      if (e == layout.vertex_element) vertex_start_ = body_size_ - tokens_.remaining();
      if (el.props.empty()) continue;
      const bool is_vertex = e == layout.vertex_element;
      const std::size_t remaining = tokens_.remaining();
      if (is_vertex) reserve_huge(out.soup.positions, io_detail::capped_reserve(el.count, remaining, 2 * el.props.size()));
      reserve_rows(layout.targets[e], io_detail::capped_reserve(el.count, remaining, 2 * el.props.size()));
      if (e == layout.face_element) reserve_faces(io_detail::capped_reserve(el.count, remaining, 8), out);
      const std::string what = "a value of element '" + el.name + "'";
      for (std::uint64_t i = 0; i < el.count; ++i)
        read_entry(el, layout.fields[e], layout.targets[e], i, is_vertex, what, out, fan);
    }
  }

  std::size_t vertex_start() const { return vertex_start_; }  // body offset of the vertex element

 private:
  double parse_value(std::string_view tok, const Element& el, const Property& prop, Role role, std::uint64_t i) const {
    double value = 0;
    if (is_position(role)) {
      if (!io_detail::parse_double(tok, value))
        tokens_.fail(fmt::format("vertex {}: invalid coordinate {}", i, quote(tok)));
      if (!std::isfinite(value)) tokens_.fail(fmt::format("vertex {} has a non-finite coordinate {}", i, quote(tok)));
    } else if (!io_detail::parse_double(tok, value)) {
      tokens_.fail(fmt::format("{} {}: invalid value {} for property '{}'", el.name, i, quote(tok), prop.name));
    }
    return value;
  }

  void read_entry(const Element& el, const std::vector<Field>& fields, const std::vector<Target>& targets,
                  std::uint64_t i, bool is_vertex, const std::string& what, ReadResult& out,
                  io_detail::FanCounter& fan) {
    double xyz[3] = {0, 0, 0};
    begin_entry(targets);
    for (std::size_t k = 0; k < el.props.size(); ++k) {
      const Property& prop = el.props[k];
      const Field& field = fields[k];
      std::string_view tok = tokens_.require(what.c_str());
      if (!prop.is_list) {
        if (field.role == Role::Skip) continue;
        const double value = parse_value(tok, el, prop, field.role, i);
        if (is_position(field.role)) xyz[static_cast<int>(field.role) - static_cast<int>(Role::X)] = value;
        if (field.target >= 0) set_value(targets, field, value);
        continue;
      }
      std::int64_t count = 0;
      if (!io_detail::parse_int(tok, count) || count < 0)
        tokens_.fail(fmt::format("{} {}: invalid list length {}", el.name, i, quote(tok)));
      if (field.role != Role::Indices) {
        for (std::int64_t j = 0; j < count; ++j) tokens_.require(what.c_str());
        continue;
      }
      if (count < 3) tokens_.fail(fmt::format("face {} has {} vertices (at least 3 needed)", i, count));
      poly_.clear();
      for (std::int64_t j = 0; j < count; ++j) {
        tok = tokens_.require("a vertex index");
        std::int64_t index = 0;
        if (!io_detail::parse_int(tok, index)) tokens_.fail(fmt::format("face {}: invalid vertex index {}", i, quote(tok)));
        if (index < 0 || static_cast<std::uint64_t>(index) >= nv_)
          tokens_.fail(fmt::format("face {}: vertex index {} out of range (file has {} vertices)", i, index, nv_));
        poly_.push_back(static_cast<int>(index));
      }
      add_polygon(poly_, out, fan);
    }
    if (is_vertex) out.soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  io_detail::TokenReader& tokens_;
  std::size_t body_size_;
  std::uint64_t nv_;
  std::size_t vertex_start_ = 0;
  std::vector<int> poly_;
};

// ---- the file, rewritten ---------------------------------------------------------------------

// What the attributes do not hold: other elements, list properties, comments.
std::string not_exposed(const Header& header, const Layout& layout) {
  std::vector<std::string> parts;
  for (std::size_t e = 0; e < header.elements.size(); ++e) {
    const Element& el = header.elements[e];
    if (e != layout.vertex_element && e != layout.face_element) {
      if (el.count > 0) parts.push_back(fmt::format("the element '{}'", el.name));
      continue;
    }
    for (std::size_t p = 0; p < el.props.size(); ++p)
      if (el.props[p].is_list && layout.fields[e][p].role != Role::Indices)
        parts.push_back(fmt::format("the list property '{}' of '{}'", el.props[p].name, el.name));
  }
  if (header.has_comments) parts.push_back("comments");
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i == 0 ? "" : i + 1 == parts.size() ? " and " : ", ") + parts[i];
  return out;
}

void copy_on_huge_pages(std::string_view from, std::string& to) {
  reserve_huge(to, from.size());
  to.assign(from);
}

// Keeps the file's bytes and its vertex element's layout; a rewrite walks the vertex element
// again (cheap next to reading it) instead of keeping per-vertex offsets.
class PlySource final : public FileSource {
 public:
  PlySource(std::string_view data, const std::string& name, const Header& header, const Layout& layout,
            std::size_t vertex_offset)
      : name_(name),
        encoding_(header.encoding),
        vertex_offset_(vertex_offset),
        vertex_count_(layout.vertex_count),
        props_(header.elements[layout.vertex_element].props) {
    for (const Field& f : layout.fields[layout.vertex_element]) {
      const bool kept = is_position(f.role) || f.role == Role::NX || f.role == Role::NY || f.role == Role::NZ;
      roles_.push_back(kept ? f.role : Role::Skip);
      has_normals_ = has_normals_ || f.role == Role::NX;
    }
    kept_only_ = not_exposed(header, layout);
    copy_on_huge_pages(data, data_);
  }

  std::string rewrite(const ReadResult& file, std::span<const Vec3> positions,
                      std::vector<std::pair<std::string, std::string>>& /*companions*/,
                      const std::string& out_path) const override {
    if (positions.size() != vertex_count_)
      throw InvalidInput(fmt::format("cannot write {}: {} positions given for the {} vertices of the PLY file", out_path,
                                     positions.size(), vertex_count_));
    std::vector<double> normals;
    if (has_normals_) {
      // Normals of polygons that kept their positions stay as the file has them.
      std::span<const Vec3> old = file.soup.positions;
      if (old.size() != vertex_count_) old = {};
      normals = recomputed_normals(file.attributes.polygons, file.attributes.normal, positions, old);
    }
    if (normals.size() != 3 * vertex_count_) normals.clear();  // not this file's attributes: keep its normals
    return encoding_ == Encoding::Ascii ? rewrite_ascii(positions, normals) : rewrite_binary(positions, normals);
  }

  bool binary() const override { return encoding_ != Encoding::Ascii; }
  std::string kept_only_by_rewrite() const override { return kept_only_; }

 private:
  // The value property `role` of vertex v gets, or nullopt to keep the file's.
  static std::optional<double> new_value(Role role, std::size_t v, std::span<const Vec3> positions,
                                         const std::vector<double>& normals) {
    if (is_position(role)) return positions[v][static_cast<int>(role) - static_cast<int>(Role::X)];
    if (role == Role::Skip || normals.empty()) return std::nullopt;
    return normals[v * 3 + static_cast<std::size_t>(static_cast<int>(role) - static_cast<int>(Role::NX))];
  }

  std::string rewrite_binary(std::span<const Vec3> positions, const std::vector<double>& normals) const {
    std::string out;
    copy_on_huge_pages(data_, out);
    auto* p = reinterpret_cast<unsigned char*>(out.data());
    const bool swap = (encoding_ == Encoding::BinaryBig) != (std::endian::native == std::endian::big);
    std::size_t pos = vertex_offset_;
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      for (std::size_t k = 0; k < props_.size(); ++k) {
        const Property& prop = props_[k];
        if (prop.is_list) {
          FF_CHECK(pos + scalar_size(prop.count_type) <= out.size(), "PLY vertex list past the end of the file");
          const auto count = static_cast<std::size_t>(load_int(prop.count_type, p + pos, swap));
          pos += scalar_size(prop.count_type) + count * scalar_size(prop.type);
          continue;
        }
        FF_CHECK(pos + scalar_size(prop.type) <= out.size(), "PLY vertex past the end of the file");
        const std::optional<double> value = new_value(roles_[k], v, positions, normals);
        // An unchanged value keeps its bytes (a -0 stays -0).
        if (value && !same_value(to_type(prop.type, *value), load_double(prop.type, p + pos, swap)))
          store_value(prop.type, *value, p + pos, swap);
        pos += scalar_size(prop.type);
      }
    }
    return out;
  }

  // Copies the text and replaces only the tokens whose value changes in the property's type, so
  // unchanged values keep their spelling ("1.000000") and every line keeps its spacing.
  std::string rewrite_ascii(std::span<const Vec3> positions, const std::vector<double>& normals) const {
    std::string out;
    reserve_huge(out, data_.size() + data_.size() / 4);
    const std::string_view rest = std::string_view(data_).substr(vertex_offset_);
    io_detail::TokenReader tokens(rest, 1, name_);
    std::size_t copied = 0;  // in `rest`
    out.append(data_, 0, vertex_offset_);
    for (std::size_t v = 0; v < vertex_count_; ++v) {
      for (std::size_t k = 0; k < props_.size(); ++k) {
        const std::string_view tok = tokens.require("a vertex value");
        if (props_[k].is_list) {
          std::int64_t count = 0;
          io_detail::parse_int(tok, count);
          for (std::int64_t j = 0; j < count; ++j) tokens.require("a vertex value");
          continue;
        }
        const std::optional<double> value = new_value(roles_[k], v, positions, normals);
        if (!value) continue;
        double old = 0;
        io_detail::parse_double(tok, old);  // checked when the file was read
        if (same_value(to_type(props_[k].type, *value), to_type(props_[k].type, old))) continue;
        const auto at = static_cast<std::size_t>(tok.data() - rest.data());
        out.append(rest.substr(copied, at - copied));
        append_value(out, props_[k].type, *value);
        copied = at + tok.size();
      }
    }
    out.append(rest.substr(copied));
    return out;
  }

  std::string data_;
  std::string name_;
  Encoding encoding_;
  std::size_t vertex_offset_;  // where the vertex element starts in data_
  std::size_t vertex_count_;
  std::vector<Property> props_;  // of the vertex element
  std::vector<Role> roles_;      // per vertex property: X..Z, NX..NZ or Skip
  bool has_normals_ = false;
  std::string kept_only_;
};

}  // namespace

void read_ply(std::string_view data, const std::string& name, ReadResult& out) {
  if (data.empty()) fail(name, 0, "empty file");
  out.soup = {};
  out.attributes = {};
  out.format = MeshFormat::Ply;
  const Header header = parse_header(data, name, out.warnings);
  Layout layout = make_layout(header, name);
  bind_attributes(header, layout, out.attributes);
  io_detail::FanCounter fan;
  const std::string_view body = data.substr(header.body_offset);
  std::size_t vertex_start = 0;
  if (header.encoding == Encoding::Ascii) {
    io_detail::TokenReader tokens(body, header.body_line, name);
    AsciiBody reader(tokens, body.size(), layout.vertex_count);
    reader.read(header, layout, out, fan);
    vertex_start = reader.vertex_start();
    std::string_view extra;
    if (tokens.next(extra))
      out.warnings.push_back(fmt::format("{}:{}: data after the last element ignored", name, tokens.line_number()));
  } else {
    const bool file_big = header.encoding == Encoding::BinaryBig;
    const bool swap = file_big != (std::endian::native == std::endian::big);
    BinaryBody reader(body, swap, name);
    reader.read(header, layout, out, fan);
    vertex_start = reader.vertex_start();
    if (reader.trailing() > 0)
      out.warnings.push_back(fmt::format("{}: {} bytes after the last element ignored", name, reader.trailing()));
  }
  io_detail::require_nonempty(out.soup, name);
  fan.warn(out.warnings);
  // PLY values are per vertex: each corner uses its vertex's row.
  if (!out.attributes.normal.values.empty()) out.attributes.normal.index = out.attributes.polygons.corners;
  if (!out.attributes.uv.values.empty()) out.attributes.uv.index = out.attributes.polygons.corners;
  out.source = std::make_shared<PlySource>(data, name, header, layout, header.body_offset + vertex_start);
}

// ---- a new file ------------------------------------------------------------------------------

namespace {

// A written scalar property: component `component` of the `width`-wide rows of `values`.
struct Column {
  std::string name;
  Scalar type = Scalar::F64;
  const double* values = nullptr;
  std::size_t width = 1;
  std::size_t component = 0;
  double scale = 1;  // colours: 255
};

const char* type_name(Scalar t) {
  switch (t) {
    case Scalar::U8: return "uchar";
    case Scalar::I32: return "int";
    case Scalar::F32: return "float";
    default: return "double";
  }
}

bool is_ply_token(std::string_view name) {
  if (name.empty()) return false;
  for (const char c : name)
    if (c <= ' ' || c > '~') return false;
  return true;
}

// Names a PLY reader gives a meaning to: writing other data under them would change it.
bool is_reserved(std::string_view name, bool vertex) {
  if (name == "vertex_indices" || name == "vertex_index") return true;
  for (const auto& names : kColorNames)
    if (std::find(names.begin(), names.end(), name) != names.end()) return true;
  if (!vertex) return false;
  if (name == "x" || name == "y" || name == "z") return true;
  if (std::find(kNormalNames.begin(), kNormalNames.end(), name) != kNormalNames.end()) return true;
  for (const auto& names : kUvNames)
    if (std::find(names.begin(), names.end(), name) != names.end()) return true;
  return false;
}

// The corner attribute's rows must exist: a bad index is the caller's bug, not a seam.
void check_corner_attribute(const Polygons& polygons, const CornerAttribute& a) {
  if (a.index.size() != polygons.corners.size())
    throw InvalidInput(fmt::format("cannot write PLY: a corner attribute has {} indices for {} polygon corners",
                                   a.index.size(), polygons.corners.size()));
  for (const int r : a.index)
    if (r >= a.rows()) throw InvalidInput(fmt::format("cannot write PLY: a corner uses row {} of {}", r, a.rows()));
}

void check_polygons(const Polygons& polygons, std::size_t nv) {
  if (polygons.offsets.empty() || polygons.offsets.front() != 0 ||
      static_cast<std::size_t>(polygons.offsets.back()) != polygons.corners.size())
    throw InvalidInput("cannot write PLY: polygon offsets do not match the corners");
  for (int p = 0; p < polygons.size(); ++p)
    if (polygons.corner_count(p) < 3)
      throw InvalidInput(fmt::format("cannot write PLY: polygon {} has {} corners", p, polygons.corner_count(p)));
  for (const int v : polygons.corners)
    if (v < 0 || static_cast<std::size_t>(v) >= nv)
      throw InvalidInput(fmt::format("cannot write PLY: vertex index {} out of range ({} vertices)", v, nv));
}

// Colour as uchar red green blue [alpha]; other attributes as double properties under their
// names (`name_0`, `name_1`, ... for wider ones). Names PLY cannot hold are dropped.
void add_named_columns(const std::vector<NamedAttribute>& named, std::size_t rows, bool vertex,
                       std::vector<Column>& columns, std::set<std::string>& used, std::vector<std::string>& dropped) {
  const char* element = vertex ? "vertex" : "face";
  for (const NamedAttribute& a : named) {
    const auto width = static_cast<std::size_t>(std::max(a.width, 0));
    if (width == 0 || a.values.size() != rows * width)
      throw InvalidInput(fmt::format("cannot write PLY: {} attribute '{}' has {} values for {} rows of width {}",
                                     element, a.name, a.values.size(), rows, a.width));
    if (a.name == "color" && (width == 3 || width == 4)) {
      if (used.count("red") != 0) {
        dropped.push_back(fmt::format("a second {} colour", element));
        continue;
      }
      for (std::size_t c = 0; c < width; ++c) {
        const std::string name(kColorNames[0][c]);
        used.insert(name);
        columns.push_back({name, Scalar::U8, a.values.data(), width, c, 255});
      }
      continue;
    }
    for (std::size_t c = 0; c < width; ++c) {
      const std::string name = width == 1 ? a.name : fmt::format("{}_{}", a.name, c);
      const char* why = !is_ply_token(name)        ? "not a valid PLY property name"
                        : is_reserved(name, vertex) ? "a name PLY readers give another meaning"
                        : used.count(name) != 0     ? "a second property with that name"
                                                    : nullptr;
      if (why != nullptr) {
        dropped.push_back(fmt::format("{} property '{}' ({})", element, name, why));
        continue;
      }
      used.insert(name);
      columns.push_back({name, Scalar::F64, a.values.data(), width, c, 1});
    }
  }
}

// Ascii values are separated by a space, also from what precedes them when `after` is set.
void append_entry(std::string& out, const std::vector<Column>& columns, std::size_t i, bool binary, bool after) {
  for (const Column& c : columns) {
    const double value = c.values[i * c.width + c.component] * c.scale;
    if (binary && c.type == Scalar::F64) {
      append_le<double>(out, value);  // the common case, without a conversion
    } else if (binary) {
      with_scalar_type(c.type, [&](auto tag) {
        using T = decltype(tag);
        append_le<T>(out, static_cast<T>(to_type(c.type, value)));
      });
    } else {
      if (after || &c != &columns.front()) out += ' ';
      if (c.type == Scalar::F64)
        io_detail::append_number(out, value);
      else
        append_value(out, c.type, value);
    }
  }
}

// The vertex columns: positions, then normals and uv where each vertex has one value.
std::vector<Column> vertex_columns(const TriangleSoup& soup, const MeshAttributes& attributes,
                                   const Polygons& polygons, std::vector<double>& normals, std::vector<double>& uv,
                                   std::vector<std::string>& dropped) {
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions are read as rows of three doubles");
  const std::size_t nv = soup.positions.size();
  std::vector<Column> columns;
  const double* xyz = nv == 0 ? nullptr : soup.positions[0].data();
  for (std::size_t k = 0; k < 3; ++k) columns.push_back({std::string(1, "xyz"[k]), Scalar::F64, xyz, 3, k, 1});
  const auto add_corner = [&](const CornerAttribute& a, int width, std::vector<double>& rows,
                              std::span<const std::string_view> names, const char* what) {
    if (a.empty()) return;
    if (a.width != width) {
      dropped.push_back(fmt::format("{} of width {} (PLY stores {})", what, a.width, width));
      return;
    }
    check_corner_attribute(polygons, a);
    std::optional<std::vector<double>> per_vertex = per_vertex_values(polygons, a, static_cast<int>(nv));
    if (!per_vertex) {
      dropped.push_back(fmt::format("{} with seams (PLY stores one per vertex)", what));
    } else {
      rows = std::move(*per_vertex);
      for (std::size_t k = 0; k < names.size(); ++k)
        columns.push_back({std::string(names[k]), Scalar::F32, rows.data(), names.size(), k, 1});
    }
  };
  add_corner(attributes.normal, 3, normals, kNormalNames, "normals");
  add_corner(attributes.uv, 2, uv, kUvNames[0], "texture coordinates");
  return columns;
}

}  // namespace

std::string write_ply(const TriangleSoup& soup, bool binary, const MeshAttributes& attributes,
                      std::vector<std::string>& dropped) {
  io_detail::check_soup_for_writing(soup);
  const std::size_t nv = soup.positions.size();
  // Without polygons the soup's triangles are written; they are copied into Polygons only when
  // corner attributes refer to them.
  const bool own = attributes.polygons.size() > 0;
  Polygons triangles;
  if (!own && (!attributes.uv.empty() || !attributes.normal.empty()))
    for (const Tri& f : soup.faces) triangles.add(f);
  const Polygons& polygons = own ? attributes.polygons : triangles;
  if (own) check_polygons(polygons, nv);
  const std::size_t nf = own ? static_cast<std::size_t>(polygons.size()) : soup.faces.size();
  const auto corners = [&](std::size_t p) {
    if (!own) return std::span<const int>(soup.faces[p]);
    const auto begin = static_cast<std::size_t>(polygons.offsets[p]);
    return std::span<const int>(polygons.corners).subspan(begin, static_cast<std::size_t>(polygons.offsets[p + 1]) - begin);
  };

  std::vector<double> normals;
  std::vector<double> uv;
  std::vector<Column> vertex = vertex_columns(soup, attributes, polygons, normals, uv, dropped);
  std::set<std::string> used;
  for (const Column& c : vertex) used.insert(c.name);
  add_named_columns(attributes.vertex, nv, true, vertex, used, dropped);
  std::vector<Column> face;
  used.clear();
  add_named_columns(attributes.face, nf, false, face, used, dropped);

  std::size_t max_corners = 3;
  for (std::size_t p = 0; own && p < nf; ++p) max_corners = std::max(max_corners, corners(p).size());
  const Scalar count_type = max_corners <= 255 ? Scalar::U8 : Scalar::I32;

  std::string out = fmt::format("ply\nformat {} 1.0\ncomment written by freeform\nelement vertex {}\n",
                                binary ? "binary_little_endian" : "ascii", nv);
  for (const Column& c : vertex) out += fmt::format("property {} {}\n", type_name(c.type), c.name);
  out += fmt::format("element face {}\nproperty list {} int vertex_indices\n", nf, type_name(count_type));
  for (const Column& c : face) out += fmt::format("property {} {}\n", type_name(c.type), c.name);
  out += "end_header\n";

  reserve_huge(out, out.size() + nv * (binary ? 24 : 64) + nf * (binary ? 13 : 32));
  for (std::size_t v = 0; v < nv; ++v) {
    append_entry(out, vertex, v, binary, false);
    if (!binary) out += '\n';
  }
  for (std::size_t p = 0; p < nf; ++p) {
    const std::span<const int> polygon = corners(p);
    if (binary) {
      if (count_type == Scalar::U8) out += static_cast<char>(static_cast<unsigned char>(polygon.size()));
      else append_le<std::int32_t>(out, static_cast<std::int32_t>(polygon.size()));
      for (const int v : polygon) append_le<std::int32_t>(out, v);
    } else {
      io_detail::append_number(out, static_cast<std::int64_t>(polygon.size()));
      for (const int v : polygon) {
        out += ' ';
        io_detail::append_number(out, static_cast<std::int64_t>(v));
      }
    }
    append_entry(out, face, p, binary, true);
    if (!binary) out += '\n';
  }
  return out;
}

}  // namespace freeform
