// Stanford PLY: ascii, binary_little_endian and binary_big_endian. Reads the vertex element's
// x, y, z (any scalar type), the face element's vertex_indices / vertex_index list (any integer
// types) and, as attributes, normals, texture coordinates, colours and every other scalar
// property of those two elements (ply_layout.cpp). The FileSource keeps the file: a rewrite
// changes only the x, y, z and nx, ny, nz values, everything else stays byte for byte
// (ply_rewrite.cpp). New files: ply_write.cpp.
#include "freeform/io/mesh_io.h"
#include "freeform/io/ply_header.h"
#include "freeform/io/ply_layout.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <cmath>

namespace freeform::ply_detail {
namespace {

using io_detail::fail;
using io_detail::quote;

// ---- what both encodings do with an entry's values ---------------------------------------------

// Appends a row of zeros to each target of an element, filled by put_scalar.
void begin_entry(const std::vector<Target>& targets) {
  for (const Target& t : targets) t.values->resize(t.values->size() + static_cast<std::size_t>(t.width));
}

// A scalar value of an entry: a coordinate of `xyz` and/or a component of its attribute row.
void put_scalar(const std::vector<Target>& targets, const Field& f, double value, double* xyz) {
  if (is_position(f.role)) xyz[component_of(f.role)] = value;
  if (f.target < 0) return;
  const Target& t = targets[static_cast<std::size_t>(f.target)];
  (*t.values)[t.values->size() - static_cast<std::size_t>(t.width - f.component)] = value * f.scale;
}

void reserve_rows(const std::vector<Target>& targets, std::size_t rows) {
  for (const Target& t : targets) reserve_huge(*t.values, rows * static_cast<std::size_t>(t.width));
}

// Room for `rows` entries of element e and, for the face element, `faces` triangles (growing
// these vectors costs more than reading the faces).
void reserve_element(const Layout& layout, std::size_t e, std::size_t rows, std::size_t faces, ReadResult& out) {
  if (e == layout.vertex_element) reserve_huge(out.soup.positions, rows);
  reserve_rows(layout.targets[e], rows);
  if (e != layout.face_element) return;
  reserve_huge(out.soup.faces, faces);
  reserve_huge(out.attributes.triangle_polygon, faces);
  reserve_huge(out.attributes.polygons.offsets, faces + 1);
  reserve_huge(out.attributes.polygons.corners, 3 * faces);
}

// Keeps a face as a polygon and its fan triangles in the soup.
void add_polygon(const std::vector<int>& poly, ReadResult& out, io_detail::FanCounter& fan) {
  const std::size_t before = out.soup.faces.size();
  fan.add(poly, out.soup.positions, out.soup.faces);
  MeshAttributes& a = out.attributes;
  a.triangle_polygon.insert(a.triangle_polygon.end(), out.soup.faces.size() - before, a.polygons.size());
  a.polygons.add(poly);
}

std::string too_few_corners(std::uint64_t face, std::int64_t count) {
  return fmt::format("face {} has {} vertices (at least 3 needed)", face, count);
}

bool index_in_range(std::int64_t index, std::uint64_t nv) {
  return index >= 0 && static_cast<std::uint64_t>(index) < nv;
}

std::string index_out_of_range(std::uint64_t face, std::int64_t index, std::uint64_t nv) {
  return fmt::format("face {}: vertex index {} out of range (file has {} vertices)", face, index, nv);
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
      reserve_element(layout, e, el.count, el.count, out);  // fits: at least one byte per value
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
      if (prop.is_list) {
        read_list(el, prop, field.role, i, nv, out, fan);
        continue;
      }
      const std::size_t s = scalar_size(prop.type);
      need(s, el, i);
      if (field.role != Role::Skip) {
        const double value = load_double(prop.type, p_ + pos_, swap_);
        if (is_position(field.role) && !std::isfinite(value))
          fail(name_, 0, fmt::format("vertex {} has a non-finite coordinate", i));
        put_scalar(targets, field, value, xyz);
      }
      pos_ += s;
    }
    if (is_vertex) out.soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  // A list property of entry i: the vertex indices become a polygon, other lists are skipped.
  void read_list(const Element& el, const Property& prop, Role role, std::uint64_t i, std::uint64_t nv,
                 ReadResult& out, io_detail::FanCounter& fan) {
    const std::size_t cs = scalar_size(prop.count_type);
    need(cs, el, i);
    const std::int64_t count = load_int(prop.count_type, p_ + pos_, swap_);
    pos_ += cs;
    if (count < 0) fail(name_, 0, fmt::format("{} {}: negative list length {}", el.name, i, count));
    const std::size_t is = scalar_size(prop.type);
    if (static_cast<std::uint64_t>(count) > (size_ - pos_) / is)
      fail(name_, 0, fmt::format("file truncated in {} {} (list of {} entries)", el.name, i, count));
    if (role != Role::Indices) {
      pos_ += static_cast<std::size_t>(count) * is;
      return;
    }
    if (count < 3) fail(name_, 0, too_few_corners(i, count));
    poly_.clear();
    for (std::int64_t j = 0; j < count; ++j) {
      const std::int64_t index = load_int(prop.type, p_ + pos_, swap_);
      pos_ += is;
      if (!index_in_range(index, nv)) fail(name_, 0, index_out_of_range(i, index, nv));
      poly_.push_back(static_cast<int>(index));
    }
    add_polygon(poly_, out, fan);
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
      reserve_element(layout, e, io_detail::capped_reserve(el.count, remaining, 2 * el.props.size()),
                      io_detail::capped_reserve(el.count, remaining, 8), out);
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
      const std::string_view tok = tokens_.require(what.c_str());
      if (prop.is_list) {
        read_list(tok, el, field.role, i, what, out, fan);
      } else if (field.role != Role::Skip) {
        put_scalar(targets, field, parse_value(tok, el, prop, field.role, i), xyz);
      }
    }
    if (is_vertex) out.soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  // A list property of entry i, `tok` its length: the vertex indices become a polygon, other
  // lists are skipped.
  void read_list(std::string_view tok, const Element& el, Role role, std::uint64_t i, const std::string& what,
                 ReadResult& out, io_detail::FanCounter& fan) {
    std::int64_t count = 0;
    if (!io_detail::parse_int(tok, count) || count < 0)
      tokens_.fail(fmt::format("{} {}: invalid list length {}", el.name, i, quote(tok)));
    if (role != Role::Indices) {
      for (std::int64_t j = 0; j < count; ++j) tokens_.require(what.c_str());
      return;
    }
    if (count < 3) tokens_.fail(too_few_corners(i, count));
    poly_.clear();
    for (std::int64_t j = 0; j < count; ++j) {
      tok = tokens_.require("a vertex index");
      std::int64_t index = 0;
      if (!io_detail::parse_int(tok, index))
        tokens_.fail(fmt::format("face {}: invalid vertex index {}", i, quote(tok)));
      if (!index_in_range(index, nv_)) tokens_.fail(index_out_of_range(i, index, nv_));
      poly_.push_back(static_cast<int>(index));
    }
    add_polygon(poly_, out, fan);
  }

  io_detail::TokenReader& tokens_;
  std::size_t body_size_;
  std::uint64_t nv_;
  std::size_t vertex_start_ = 0;
  std::vector<int> poly_;
};

// Reads the body after the header; returns where the vertex element starts in it.
std::size_t read_body(std::string_view body, const std::string& name, const Header& header, const Layout& layout,
                      ReadResult& out, io_detail::FanCounter& fan) {
  if (header.encoding == Encoding::Ascii) {
    io_detail::TokenReader tokens(body, header.body_line, name);
    AsciiBody reader(tokens, body.size(), layout.vertex_count);
    reader.read(header, layout, out, fan);
    std::string_view extra;
    if (tokens.next(extra))
      out.warnings.push_back(fmt::format("{}:{}: data after the last element ignored", name, tokens.line_number()));
    return reader.vertex_start();
  }
  BinaryBody reader(body, needs_swap(header.encoding), name);
  reader.read(header, layout, out, fan);
  if (reader.trailing() > 0)
    out.warnings.push_back(fmt::format("{}: {} bytes after the last element ignored", name, reader.trailing()));
  return reader.vertex_start();
}

}  // namespace
}  // namespace freeform::ply_detail

namespace freeform {

void read_ply(std::string_view data, const std::string& name, ReadResult& out) {
  using namespace ply_detail;
  if (data.empty()) io_detail::fail(name, 0, "empty file");
  out.soup = {};
  out.attributes = {};
  out.format = MeshFormat::Ply;
  const Header header = parse_header(data, name, out.warnings);
  Layout layout = make_layout(header, name);
  bind_attributes(header, layout, out.attributes);
  io_detail::FanCounter fan;
  const std::size_t vertex_start = read_body(data.substr(header.body_offset), name, header, layout, out, fan);
  io_detail::require_nonempty(out.soup, name);
  fan.warn(out.warnings);
  // PLY values are per vertex: each corner uses its vertex's row.
  if (!out.attributes.normal.values.empty()) out.attributes.normal.index = out.attributes.polygons.corners;
  if (!out.attributes.uv.values.empty()) out.attributes.uv.index = out.attributes.polygons.corners;
  out.source = make_ply_source(file_bytes(data, out), name, header, layout, header.body_offset + vertex_start);
}

}  // namespace freeform
