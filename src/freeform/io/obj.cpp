// Wavefront OBJ: positions (and `v x y z r g b` colours), `vt`, `vn` and `f` with any corner
// form; everything else (groups, materials, smoothing, comments) is kept by the FileSource.
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/obj_libraries.h"
#include "freeform/io/text_patch.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace freeform {
namespace {

using io_detail::fail;
using io_detail::quote;

// True when the last non-blank character of `line` is a backslash (line continuation).
bool continues(std::string_view line) {
  std::size_t n = line.size();
  while (n > 0 && io_detail::is_space(line[n - 1])) --n;
  return n > 0 && line[n - 1] == '\\';
}

std::string_view without_backslash(std::string_view line) {
  std::size_t n = line.size();
  while (n > 0 && io_detail::is_space(line[n - 1])) --n;
  return line.substr(0, n - 1);
}

bool is_comment(std::string_view line) {
  for (char c : line) {
    if (!io_detail::is_space(c)) return c == '#';
  }
  return false;
}

// An index that refers past the elements seen so far (OBJ allows it); checked at the end.
struct ForwardRef {
  std::size_t line;
  std::size_t face;
  long long index;
  int kind;  // 0 vertex, 1 texture coordinate, 2 normal
};

constexpr const char* kKindNames[3] = {"vertex", "texture coordinate", "normal"};
constexpr const char* kKindPlurals[3] = {"vertices", "texture coordinates", "normals"};

constexpr std::pair<std::string_view, const char*> kNames[] = {
    {"g", "groups"},           {"o", "objects"}, {"usemtl", "materials"}, {"mtllib", "material libraries"},
    {"s", "smoothing groups"}, {"l", "lines"},   {"p", "points"}};

class OtherStatements {
 public:
  void saw(std::string_view keyword) {
    for (std::size_t i = 0; i < std::size(kNames); ++i)
      if (keyword == kNames[i].first) seen_ |= 1u << i;
  }
  std::string names() const {
    std::string out;
    for (std::size_t i = 0; i < std::size(kNames); ++i)
      if (seen_ & (1u << i)) out += (out.empty() ? "" : ", ") + std::string(kNames[i].second);
    return out;
  }

 private:
  unsigned seen_ = 0;
};

// The statements of an OBJ file the mesh is made of, read line by line.
class ObjReader {
 public:
  ObjReader(std::string_view data, const std::string& name, ReadResult& out) : data_(data), name_(name), out_(out) {
    reserve();
  }

  void statement(std::string_view line, std::size_t line_no, bool joined) {
    line_ = line_no;
    io_detail::Tokens tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) return;
    if (keyword == "v") {
      vertex(tokens, joined);
    } else if (keyword == "vt") {
      rows(tokens, uv_, 2, "texture coordinate", 1);
    } else if (keyword == "vn") {
      const std::string_view first = rows(tokens, normal_, 3, "normal", 3);
      if (joined)
        rewritable_ = false;
      else
        normal_runs_.push_back(io_detail::span_of(data_, first, last_));
    } else if (keyword == "f") {
      face(tokens);
    } else {
      other_.saw(keyword);
      has_libraries_ = has_libraries_ || keyword == "mtllib";
    }
    // vp, g, o, s, usemtl, mtllib, l, p, comments, ...: kept by the source, not read.
  }

  void finish(std::vector<std::string>& warnings) {
    const long long counts[3] = {static_cast<long long>(out_.soup.positions.size()), uv_.rows(), normal_.rows()};
    for (const ForwardRef& ref : forward_)
      if (ref.index > counts[ref.kind])
        fail(name_, ref.line,
             fmt::format("face {}: {} index {} out of range (file has {} {})", ref.face, kKindNames[ref.kind],
                         ref.index, counts[ref.kind], kKindPlurals[ref.kind]));
    io_detail::require_nonempty(out_.soup, name_);
    fan_.warn(warnings);
    MeshAttributes& a = out_.attributes;
    if (has_uv_) a.uv = {2, std::move(uv_.values), std::move(uv_index_)};
    if (has_normal_)
      a.normal = {3, std::move(normal_.values), std::move(normal_index_)};
    else
      normal_runs_.clear();  // `vn` rows no face uses are not recomputed: kept as written
    if (has_color_) {
      colors_.resize(out_.soup.positions.size() * 3, 1.0);
      a.vertex.push_back({"color", 3, std::move(colors_)});
    }
    io_detail::Relink relink;
    if (has_libraries_)
      relink = [folder = folder_of(name_)](std::string text, const std::string& out_path) {
        return io_detail::relink_material_libraries(std::move(text), folder, out_path);
      };
    if (rewritable_)
      out_.source = io_detail::make_text_source(file_bytes(data_, out_), std::move(position_runs_),
                                                std::move(normal_runs_), other_.names(), std::move(relink));
  }

 private:
  void vertex(io_detail::Tokens& tokens, bool joined) {
    std::vector<Vec3>& positions = out_.soup.positions;
    if (positions.size() >= io_detail::kMaxElements) fail(name_, line_, "too many vertices");
    double xyz[3];
    std::string_view first;
    for (int k = 0; k < 3; ++k) {
      std::string_view tok;
      if (!tokens.next(tok)) fail(name_, line_, fmt::format("vertex {} has fewer than 3 coordinates", positions.size()));
      xyz[k] = number(tok, "vertex", positions.size(), "coordinate");
      if (k == 0) first = tok;
      last_ = tok;
    }
    if (joined)
      rewritable_ = false;
    else
      position_runs_.push_back(io_detail::span_of(data_, first, last_));
    // `v x y z r g b` (the common vertex-colour extension); `v x y z w` keeps its weight.
    std::string_view extra[4];
    int n_extra = 0;
    while (n_extra < 4 && tokens.next(extra[n_extra])) ++n_extra;
    if (n_extra == 3) {
      colors_.resize(positions.size() * 3, 1.0);
      for (int k = 0; k < 3; ++k) colors_.push_back(number(extra[k], "vertex", positions.size(), "colour"));
      has_color_ = true;
    }
    positions.emplace_back(xyz[0], xyz[1], xyz[2]);
  }

  // A `vt` or `vn` row: `width` numbers (at least `required`), missing ones 0.
  std::string_view rows(io_detail::Tokens& tokens, CornerAttribute& into, int width, const char* what, int required) {
    const std::size_t row = into.values.size() / static_cast<std::size_t>(width);
    std::string_view first, tok;
    for (int k = 0; k < width; ++k) {
      if (!tokens.next(tok)) {
        if (k < required) fail(name_, line_, fmt::format("{} {} has fewer than {} values", what, row, required));
        into.values.push_back(0.0);
        continue;
      }
      into.values.push_back(number(tok, what, row, "value"));
      if (k == 0) first = tok;
      last_ = tok;
    }
    into.width = width;
    return first;
  }

  // Counts `v` and `f` lines first (a fast scan) so the arrays grow once, not by doubling.
  void reserve() {
    std::size_t vertices = 0, faces = 0;
    for (std::size_t pos = 0; pos < data_.size();) {
      const std::size_t end = std::min(data_.find('\n', pos), data_.size());
      if (end - pos >= 2 && io_detail::is_space(data_[pos + 1])) {
        vertices += data_[pos] == 'v';
        faces += data_[pos] == 'f';
      }
      pos = end + 1;
    }
    out_.soup.positions.reserve(vertices);
    position_runs_.reserve(vertices);
    out_.soup.faces.reserve(faces);
    out_.attributes.triangle_polygon.reserve(faces);
    out_.attributes.polygons.offsets.reserve(faces + 1);
    out_.attributes.polygons.corners.reserve(3 * faces);
  }

  double number(std::string_view tok, const char* what, std::size_t i, const char* part) const {
    double value = 0;
    if (!io_detail::parse_double(tok, value)) fail(name_, line_, fmt::format("{} {}: invalid {} {}", what, i, part, quote(tok)));
    if (!std::isfinite(value))
      fail(name_, line_, fmt::format("{} {} has a non-finite {} {}", what, i, part, quote(tok)));
    return value;
  }

  // One index of a face corner (1-based or negative = relative); -1 when absent.
  int index(std::string_view part, int kind, std::string_view corner) {
    if (part.empty()) {
      if (kind == 0) fail(name_, line_, fmt::format("face {}: invalid vertex index {}", face_count_, quote(corner)));
      return -1;
    }
    const long long count = kind == 0 ? static_cast<long long>(out_.soup.positions.size())
                                      : (kind == 1 ? uv_.rows() : normal_.rows());
    long long i = 0;
    if (!io_detail::parse_int(part, i))
      fail(name_, line_, fmt::format("face {}: invalid {} index {}", face_count_, kKindNames[kind], quote(corner)));
    if (i == 0)
      fail(name_, line_,
           fmt::format("face {}: {} index 0 is invalid (OBJ indices start at 1)", face_count_, kKindNames[kind]));
    if (i < 0) {
      if (-i > count)
        fail(name_, line_,
             fmt::format("face {}: relative {} index {} reaches before the first {} ({} {} so far)", face_count_,
                         kKindNames[kind], i, kKindNames[kind], count, kKindPlurals[kind]));
      return static_cast<int>(count + i);
    }
    if (static_cast<unsigned long long>(i) > io_detail::kMaxElements)
      fail(name_, line_, fmt::format("face {}: {} index {} out of range", face_count_, kKindNames[kind], i));
    if (i > count) forward_.push_back({line_, face_count_, i, kind});
    return static_cast<int>(i - 1);
  }

  // Rows are kept from the first corner that has one (earlier corners: -1), so a file without
  // `vt` or `vn` costs nothing.
  static void corner_row(std::vector<int>& rows, int row, std::size_t corner, bool& seen) {
    if (row >= 0 && !seen) {
      seen = true;
      rows.assign(corner, -1);
    }
    if (seen) rows.push_back(row);
  }

  void face(io_detail::Tokens& tokens) {
    poly_.clear();
    std::string_view tok;
    while (tokens.next(tok) && tok[0] != '#') {
      const std::size_t s1 = tok.find('/');
      const std::string_view head = tok.substr(0, s1);
      std::string_view tex, nrm;
      if (s1 != std::string_view::npos) {
        const std::string_view rest = tok.substr(s1 + 1);
        const std::size_t s2 = rest.find('/');
        tex = rest.substr(0, s2);
        if (s2 != std::string_view::npos) nrm = rest.substr(s2 + 1);
      }
      const std::size_t corner = out_.attributes.polygons.corners.size() + poly_.size();
      poly_.push_back(index(head, 0, tok));
      corner_row(uv_index_, index(tex, 1, tok), corner, has_uv_);
      corner_row(normal_index_, index(nrm, 2, tok), corner, has_normal_);
    }
    if (poly_.size() < 3)
      fail(name_, line_, fmt::format("face {} has {} vertices (at least 3 needed)", face_count_, poly_.size()));
    fan_.add(poly_, out_.soup.positions, out_.soup.faces, &out_.attributes);
    ++face_count_;
  }

  std::string_view data_;
  const std::string& name_;
  ReadResult& out_;
  std::size_t line_ = 0;
  std::size_t face_count_ = 0;
  std::string_view last_;
  io_detail::FanCounter fan_;
  std::vector<int> poly_;
  std::vector<ForwardRef> forward_;
  CornerAttribute uv_, normal_;
  std::vector<int> uv_index_, normal_index_;
  std::vector<double> colors_;
  bool has_uv_ = false, has_normal_ = false, has_color_ = false;
  bool has_libraries_ = false;  // an `mtllib` statement
  bool rewritable_ = true;
  OtherStatements other_;
  std::vector<io_detail::TextSpan> position_runs_, normal_runs_;
};

}  // namespace

void read_obj(std::string_view data, const std::string& name, ReadResult& out) {
  if (data.empty()) fail(name, 0, "empty file");
  out.format = MeshFormat::Obj;
  io_detail::LineReader lines(data, name);
  ObjReader reader(data, name, out);
  std::string joined;
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t line_no = lines.line_number();
    const bool join = continues(line) && !is_comment(line);
    if (join) {
      joined.assign(without_backslash(line));
      std::string_view more;
      bool open = true;
      while (open && lines.next(more)) {
        joined += ' ';
        open = continues(more);
        joined.append(open ? without_backslash(more) : more);
      }
      line = joined;
    }
    reader.statement(line, line_no, join);
  }
  reader.finish(out.warnings);
}

namespace {

void append_row(std::string& out, const char* keyword, const double* values, int width) {
  out += keyword;
  for (int k = 0; k < width; ++k) {
    out += ' ';
    io_detail::append_number(out, values[k]);
  }
  out += '\n';
}

void append_corner(std::string& out, int vertex, int uv, int normal) {
  out += ' ';
  io_detail::append_number(out, static_cast<std::int64_t>(vertex) + 1);
  if (uv < 0 && normal < 0) return;
  out += '/';
  if (uv >= 0) io_detail::append_number(out, static_cast<std::int64_t>(uv) + 1);
  if (normal < 0) return;
  out += '/';
  io_detail::append_number(out, static_cast<std::int64_t>(normal) + 1);
}

}  // namespace

std::string write_obj(const TriangleSoup& soup, const MeshAttributes& attributes, std::vector<std::string>& dropped) {
  io_detail::check_soup_for_writing(soup);
  const Polygons& polygons = attributes.polygons;
  const bool keep_polygons = polygons.size() > 0;
  const NamedAttribute* color = attributes.vertex_attribute("color");
  std::string out;
  out.reserve(soup.positions.size() * 64 + soup.faces.size() * 32 + 64);
  out += "# freeform: ";
  io_detail::append_number(out, static_cast<std::int64_t>(soup.positions.size()));
  out += " vertices, ";
  io_detail::append_number(out, static_cast<std::int64_t>(keep_polygons ? polygons.size() : soup.faces.size()));
  out += keep_polygons ? " faces\n" : " triangles\n";
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      io_detail::append_number(out, soup.positions[v][k]);
    }
    // OBJ's colour extension has no alpha: r g b only.
    for (int k = 0; color != nullptr && k < 3; ++k) {
      out += ' ';
      io_detail::append_number(out, color->values[v * static_cast<std::size_t>(color->width) + static_cast<std::size_t>(k)]);
    }
    out += '\n';
  }
  const bool uv = keep_polygons && !attributes.uv.empty(), normal = keep_polygons && !attributes.normal.empty();
  for (int r = 0; uv && r < attributes.uv.rows(); ++r) append_row(out, "vt", &attributes.uv.values[static_cast<std::size_t>(r) * 2], 2);
  for (int r = 0; normal && r < attributes.normal.rows(); ++r)
    append_row(out, "vn", &attributes.normal.values[static_cast<std::size_t>(r) * 3], 3);
  if (!keep_polygons) {
    for (const Tri& f : soup.faces) {
      out += 'f';
      for (int v : f) append_corner(out, v, -1, -1);
      out += '\n';
    }
  }
  for (int p = 0; p < polygons.size(); ++p) {
    out += 'f';
    for (int c = polygons.offsets[static_cast<std::size_t>(p)]; c < polygons.offsets[static_cast<std::size_t>(p) + 1]; ++c) {
      const auto i = static_cast<std::size_t>(c);
      append_corner(out, polygons.corners[i], uv ? attributes.uv.index[i] : -1, normal ? attributes.normal.index[i] : -1);
    }
    out += '\n';
  }
  if (color != nullptr && color->width == 4) dropped.push_back("vertex colour alpha (OBJ colours are r g b)");
  for (const NamedAttribute& a : attributes.vertex)
    if (a.name != "color") dropped.push_back(fmt::format("vertex property '{}' (OBJ has no custom properties)", a.name));
  for (const NamedAttribute& a : attributes.face)
    dropped.push_back(fmt::format("face property '{}' (OBJ has no face properties)", a.name));
  return out;
}

}  // namespace freeform
