// A new PLY file from a soup and its attributes: positions, per-vertex normals and texture
// coordinates, colours and other named attributes of vertices and faces, and the polygons
// (or the soup's triangles).
#include "freeform/io/mesh_io.h"
#include "freeform/io/ply_header.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <set>
#include <span>

namespace freeform::ply_detail {
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

template <class Names>
bool contains(const Names& names, std::string_view name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// Names a PLY reader gives a meaning to: writing other data under them would change it.
bool is_reserved(std::string_view name, bool vertex) {
  if (name == "vertex_indices" || name == "vertex_index") return true;
  for (const auto& names : kColorNames)
    if (contains(names, name)) return true;
  if (!vertex) return false;
  if (contains(kPositionNames, name) || contains(kNormalNames, name)) return true;
  for (const auto& names : kUvNames)
    if (contains(names, name)) return true;
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
      append_binary(out, c.type, value);
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
  for (std::size_t k = 0; k < 3; ++k) columns.push_back({std::string(kPositionNames[k]), Scalar::F64, xyz, 3, k, 1});
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

std::string header_text(bool binary, std::size_t nv, const std::vector<Column>& vertex, std::size_t nf,
                        Scalar count_type, const std::vector<Column>& face) {
  std::string out = fmt::format("ply\nformat {} 1.0\ncomment written by freeform\nelement vertex {}\n",
                                binary ? "binary_little_endian" : "ascii", nv);
  for (const Column& c : vertex) out += fmt::format("property {} {}\n", type_name(c.type), c.name);
  out += fmt::format("element face {}\nproperty list {} int vertex_indices\n", nf, type_name(count_type));
  for (const Column& c : face) out += fmt::format("property {} {}\n", type_name(c.type), c.name);
  out += "end_header\n";
  return out;
}

// A face's vertex_indices list: its length in `count_type`, then the indices as int.
void append_indices(std::string& out, std::span<const int> polygon, bool binary, Scalar count_type) {
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
}

}  // namespace
}  // namespace freeform::ply_detail

namespace freeform {

std::string write_ply(const TriangleSoup& soup, bool binary, const MeshAttributes& attributes,
                      std::vector<std::string>& dropped) {
  using namespace ply_detail;
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
    const auto end = static_cast<std::size_t>(polygons.offsets[p + 1]);
    return std::span<const int>(polygons.corners).subspan(begin, end - begin);
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

  std::string out = header_text(binary, nv, vertex, nf, count_type, face);
  reserve_huge(out, out.size() + nv * (binary ? 24 : 64) + nf * (binary ? 13 : 32));
  for (std::size_t v = 0; v < nv; ++v) {
    append_entry(out, vertex, v, binary, false);
    if (!binary) out += '\n';
  }
  for (std::size_t p = 0; p < nf; ++p) {
    append_indices(out, corners(p), binary, count_type);
    append_entry(out, face, p, binary, true);
    if (!binary) out += '\n';
  }
  return out;
}

}  // namespace freeform
