// Geomview OFF ([ST][C][N][4][n]OFF), ascii only. One vertex or face per line: coordinates, then
// the normal (N), colour (C) and texture coordinates (ST) the keyword declares; a face's indices,
// then an optional colour. '#' starts a comment anywhere.
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_patch.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace freeform {
namespace {

using io_detail::fail;
using io_detail::quote;

std::string_view strip_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

// Next line with any content (comments removed); false at the end of the file.
bool next_content_line(io_detail::LineReader& lines, std::string_view& line) {
  while (lines.next(line)) {
    line = strip_comment(line);
    if (!io_detail::Tokens(line).at_end()) return true;
  }
  return false;
}

struct Header {
  bool uv = false, color = false, normal = false;  // ST, C, N: per-vertex values after x y z
  bool homogeneous = false;  // 4OFF: x y z w
  bool has_dim = false;      // nOFF: dimension given before the counts
};

bool parse_keyword(std::string_view kw, Header& header) {
  auto eat = [&kw](std::string_view prefix) {
    if (kw.substr(0, prefix.size()) != prefix) return false;
    kw.remove_prefix(prefix.size());
    return true;
  };
  header.uv = eat("ST");
  header.color = eat("C");
  header.normal = eat("N");
  header.homogeneous = eat("4");
  header.has_dim = eat("n");
  return kw == "OFF";
}

// A colour attribute from r g b a rows: 0..255 or 0..1 (a file with any component above 1 is
// scaled by 1/255); alpha dropped when the file gave none.
NamedAttribute color_attribute(std::vector<double> rgba, bool alpha) {
  if (std::any_of(rgba.begin(), rgba.end(), [](double c) { return c > 1.0; }))
    for (double& c : rgba) c /= 255.0;
  if (alpha) return {"color", 4, std::move(rgba)};
  std::vector<double> rgb;
  rgb.reserve(rgba.size() / 4 * 3);
  for (std::size_t i = 0; i < rgba.size(); i += 4) rgb.insert(rgb.end(), rgba.begin() + static_cast<std::ptrdiff_t>(i), rgba.begin() + static_cast<std::ptrdiff_t>(i + 3));
  return {"color", 3, std::move(rgb)};
}

struct Counts {
  std::uint64_t vertices = 0, faces = 0;
};

Counts read_header(io_detail::LineReader& lines, std::string_view& line, Header& header) {
  if (!next_content_line(lines, line)) fail(lines.name(), lines.line_number(), "empty file (no OFF header)");
  io_detail::Tokens tokens(line);
  std::string_view keyword;
  tokens.next(keyword);
  if (!parse_keyword(keyword, header))
    lines.fail(
        fmt::format("missing OFF header: expected OFF, COFF, NOFF, STOFF, 4OFF, ... but found {}", quote(keyword)));
  {
    io_detail::Tokens peek = tokens;
    std::string_view tok;
    if (peek.next(tok) && tok == "BINARY") lines.fail("binary OFF is not supported (only ascii OFF)");
  }
  // Counts: on the header line or on the following lines. The rest of the line holding the face
  // count (usually the edge count) is ignored.
  auto header_value = [&](const char* what) {
    std::string_view tok;
    while (!tokens.next(tok)) {
      if (!next_content_line(lines, line)) lines.fail(fmt::format("unexpected end of file (expected {})", what));
      tokens = io_detail::Tokens(line);
    }
    std::uint64_t value = 0;
    if (!io_detail::parse_int(tok, value)) lines.fail(fmt::format("invalid {} {}", what, quote(tok)));
    return value;
  };
  if (header.has_dim) {
    const std::uint64_t d = header_value("dimension");
    if (d != 3) lines.fail(fmt::format("only 3-dimensional nOFF files are supported (dimension {})", d));
  }
  Counts counts;
  counts.vertices = header_value("vertex count");
  counts.faces = header_value("face count");
  if (counts.vertices > io_detail::kMaxElements) lines.fail(fmt::format("vertex count {} is too large", counts.vertices));
  if (counts.faces > io_detail::kMaxElements) lines.fail(fmt::format("face count {} is too large", counts.faces));
  if (counts.vertices == 0) lines.fail("no vertices (vertex count is 0)");
  if (counts.faces == 0) lines.fail("no faces (face count is 0)");
  return counts;
}

// Up to `max` numbers left on a line (fewer when a token is not a number).
int rest_numbers(io_detail::Tokens& tokens, double* values, int max) {
  int n = 0;
  std::string_view tok;
  while (n < max && tokens.next(tok) && io_detail::parse_double(tok, values[n]) && std::isfinite(values[n])) ++n;
  return n;
}

struct VertexExtras {
  std::vector<double> normals, colors, uv;  // colours as r g b a
  bool alpha = false;                          // some colour had 4 values
  std::vector<io_detail::TextSpan> position_runs, normal_runs;
};

// x y z [w], then the values the keyword declares: normal (3), colour (3 or 4), uv (2).
void read_vertex(std::string_view data, io_detail::LineReader& lines, std::string_view line, std::uint64_t i,
                 const Header& header, TriangleSoup& soup, VertexExtras& extras) {
  io_detail::Tokens tokens(line);
  const std::size_t coords = header.homogeneous ? 4 : 3;
  double c[4] = {0, 0, 0, 1};
  std::string_view first, last;
  for (std::size_t k = 0; k < coords; ++k) {
    std::string_view tok;
    if (!tokens.next(tok)) lines.fail(fmt::format("vertex {} has fewer than {} coordinates", i, coords));
    if (!io_detail::parse_double(tok, c[k])) lines.fail(fmt::format("vertex {}: invalid coordinate {}", i, quote(tok)));
    if (!std::isfinite(c[k])) lines.fail(fmt::format("vertex {} has a non-finite coordinate {}", i, quote(tok)));
    if (k == 0) first = tok;
    last = tok;
  }
  if (header.homogeneous) {
    if (c[3] == 0.0) lines.fail(fmt::format("vertex {} has homogeneous coordinate w = 0", i));
    for (int k = 0; k < 3; ++k) c[k] /= c[3];
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
      lines.fail(fmt::format("vertex {} is not finite after dividing by w", i));
  }
  extras.position_runs.push_back(io_detail::span_of(data, first, last));
  soup.positions.emplace_back(c[0], c[1], c[2]);
  double rest[9];
  io_detail::Tokens probe = tokens;
  const int n = rest_numbers(probe, rest, 9);
  const int n_normal = header.normal ? 3 : 0, n_uv = header.uv ? 2 : 0;
  const int n_color = header.color ? n - n_normal - n_uv : 0;
  if (n < n_normal + n_uv || (header.color && n_color != 3 && n_color != 4))
    lines.fail(fmt::format("vertex {} has {} values after its coordinates; the header declares{}{}{}", i, n,
                           header.normal ? " a normal" : "", header.color ? " a colour (3 or 4 values)" : "",
                           header.uv ? " texture coordinates" : ""));
  if (header.normal) {
    std::string_view tok, nfirst, nlast;
    for (int k = 0; k < 3; ++k) {
      tokens.next(tok);
      if (k == 0) nfirst = tok;
      nlast = tok;
    }
    extras.normal_runs.push_back(io_detail::span_of(data, nfirst, nlast));
    extras.normals.insert(extras.normals.end(), rest, rest + 3);
  }
  if (header.color) {
    extras.alpha = extras.alpha || n_color == 4;
    extras.colors.insert(extras.colors.end(), rest + n_normal, rest + n_normal + 4);
    if (n_color == 3) extras.colors.back() = 1.0;
  }
  if (header.uv) extras.uv.insert(extras.uv.end(), rest + n_normal + n_color, rest + n_normal + n_color + 2);
}

}  // namespace

void read_off(std::string_view data, const std::string& name, ReadResult& out) {
  if (data.empty()) fail(name, 0, "empty file");
  out.format = MeshFormat::Off;
  io_detail::LineReader lines(data, name);
  std::string_view line;
  Header header;
  const auto [nv, nf] = read_header(lines, line, header);
  TriangleSoup& soup = out.soup;
  VertexExtras extras;
  soup.positions.reserve(io_detail::capped_reserve(nv, lines.remaining(), header.homogeneous ? 8 : 6));
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!next_content_line(lines, line))
      lines.fail(fmt::format("unexpected end of file: header declares {} vertices, found {}", nv, i));
    read_vertex(data, lines, line, i, header, soup, extras);
  }

  io_detail::FanCounter fan;
  std::vector<int> poly;
  std::vector<double> face_colors;
  bool all_faces_colored = true, face_alpha = false;
  soup.faces.reserve(io_detail::capped_reserve(nf, lines.remaining(), 8));
  for (std::uint64_t f = 0; f < nf; ++f) {
    if (!next_content_line(lines, line))
      lines.fail(fmt::format("unexpected end of file: header declares {} faces, found {}", nf, f));
    io_detail::Tokens tokens(line);
    std::string_view tok;
    tokens.next(tok);
    std::uint64_t n = 0;
    if (!io_detail::parse_int(tok, n)) lines.fail(fmt::format("face {}: invalid vertex count {}", f, quote(tok)));
    if (n < 3) lines.fail(fmt::format("face {} has {} vertices (at least 3 needed)", f, n));
    poly.clear();
    for (std::uint64_t k = 0; k < n; ++k) {
      if (!tokens.next(tok)) lines.fail(fmt::format("face {} declares {} vertices but lists only {}", f, n, k));
      long long index = 0;
      if (!io_detail::parse_int(tok, index)) lines.fail(fmt::format("face {}: invalid vertex index {}", f, quote(tok)));
      if (index < 0 || static_cast<unsigned long long>(index) >= nv)
        lines.fail(fmt::format("face {}: vertex index {} out of range (file has {} vertices)", f, index, nv));
      poly.push_back(static_cast<int>(index));
    }
    fan.add(poly, soup.positions, soup.faces, &out.attributes);
    double color[4] = {1, 1, 1, 1};
    const int n_color = rest_numbers(tokens, color, 4);  // a colour-map index (1 value) is not kept
    all_faces_colored = all_faces_colored && n_color >= 3;
    face_alpha = face_alpha || n_color == 4;
    face_colors.insert(face_colors.end(), color, color + 4);
  }
  if (next_content_line(lines, line))
    out.warnings.push_back(fmt::format("{}:{}: data after the last face ignored", name, lines.line_number()));
  fan.warn(out.warnings);

  MeshAttributes& a = out.attributes;
  const std::vector<int> by_vertex(a.polygons.corners);
  if (header.normal) a.normal = {3, extras.normals, by_vertex};
  if (header.uv) a.uv = {2, std::move(extras.uv), by_vertex};
  if (header.color) a.vertex.push_back(color_attribute(std::move(extras.colors), extras.alpha));
  if (all_faces_colored) a.face.push_back(color_attribute(std::move(face_colors), face_alpha));
  // Homogeneous and n-dimensional files are written as plain OFF (their w is not kept).
  if (!header.homogeneous && !header.has_dim)
    out.source = io_detail::make_text_source(file_bytes(data, out), std::move(extras.position_runs),
                                             std::move(extras.normal_runs), "");
}

namespace {

void append_values(std::string& out, const std::vector<double>& values, std::size_t row, int width) {
  for (int k = 0; k < width; ++k) {
    out += ' ';
    io_detail::append_number(out, values[row * static_cast<std::size_t>(width) + static_cast<std::size_t>(k)]);
  }
}

// A corner attribute as per-vertex values, or empty (and a note in `dropped`) at a seam.
std::vector<double> vertex_values(const MeshAttributes& a, const CornerAttribute& c, int n_vertices, const char* what,
                                  std::vector<std::string>& dropped) {
  if (c.empty() || a.polygons.size() == 0) return {};
  std::optional<std::vector<double>> values = per_vertex_values(a.polygons, c, n_vertices);
  if (!values) dropped.push_back(fmt::format("{} with seams (OFF stores one per vertex)", what));
  return values ? std::move(*values) : std::vector<double>{};
}

}  // namespace

std::string write_off(const TriangleSoup& soup, const MeshAttributes& attributes, std::vector<std::string>& dropped) {
  io_detail::check_soup_for_writing(soup);
  const int n = static_cast<int>(soup.positions.size());
  const std::vector<double> normals = vertex_values(attributes, attributes.normal, n, "normals", dropped);
  const std::vector<double> uv = vertex_values(attributes, attributes.uv, n, "texture coordinates", dropped);
  const NamedAttribute* color = attributes.vertex_attribute("color");
  const NamedAttribute* face_color = nullptr;
  for (const NamedAttribute& a : attributes.face)
    if (a.name == "color") face_color = &a;
  const Polygons& polygons = attributes.polygons;
  const bool keep_polygons = polygons.size() > 0;
  std::string out;
  out.reserve(soup.positions.size() * 64 + soup.faces.size() * 32 + 64);
  out += fmt::format("{}{}{}OFF\n", uv.empty() ? "" : "ST", color ? "C" : "", normals.empty() ? "" : "N");
  io_detail::append_number(out, static_cast<std::int64_t>(n));
  out += ' ';
  io_detail::append_number(out, static_cast<std::int64_t>(keep_polygons ? polygons.size() : soup.faces.size()));
  out += " 0\n";
  for (std::size_t v = 0; v < soup.positions.size(); ++v) {
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out += ' ';
      io_detail::append_number(out, soup.positions[v][k]);
    }
    if (!normals.empty()) append_values(out, normals, v, 3);
    if (color != nullptr) append_values(out, color->values, v, color->width);
    if (!uv.empty()) append_values(out, uv, v, 2);
    out += '\n';
  }
  const int n_faces = keep_polygons ? polygons.size() : static_cast<int>(soup.faces.size());
  for (int f = 0; f < n_faces; ++f) {
    const auto p = static_cast<std::size_t>(f);
    const std::span<const int> corners =
        keep_polygons ? std::span<const int>(polygons.corners).subspan(static_cast<std::size_t>(polygons.offsets[p]),
                                                                        static_cast<std::size_t>(polygons.corner_count(f)))
                      : std::span<const int>(soup.faces[p]);
    io_detail::append_number(out, static_cast<std::int64_t>(corners.size()));
    for (const int v : corners) {
      out += ' ';
      io_detail::append_number(out, static_cast<std::int64_t>(v));
    }
    if (face_color != nullptr && keep_polygons) append_values(out, face_color->values, p, face_color->width);
    out += '\n';
  }
  for (const NamedAttribute& a : attributes.vertex)
    if (a.name != "color") dropped.push_back(fmt::format("vertex property '{}' (OFF has no custom properties)", a.name));
  for (const NamedAttribute& a : attributes.face)
    if (a.name != "color") dropped.push_back(fmt::format("face property '{}' (OFF has no custom properties)", a.name));
  return out;
}

}  // namespace freeform
