// Geomview OFF ([ST][C][N][4][n]OFF), ascii only. One vertex or face per line; values after the
// coordinates (normals, colours, texture coordinates) and after a face's indices (colour) are
// ignored; '#' starts a comment anywhere.
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

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
  bool homogeneous = false;  // 4OFF: x y z w
  bool has_dim = false;      // nOFF: dimension given before the counts
};

bool parse_keyword(std::string_view kw, Header& header) {
  auto eat = [&kw](std::string_view prefix) {
    if (kw.substr(0, prefix.size()) != prefix) return false;
    kw.remove_prefix(prefix.size());
    return true;
  };
  eat("ST");
  eat("C");
  eat("N");
  header.homogeneous = eat("4");
  header.has_dim = eat("n");
  return kw == "OFF";
}

}  // namespace

TriangleSoup read_off(std::string_view data, const std::string& name, std::vector<std::string>& warnings) {
  if (data.empty()) fail(name, 0, "empty file");
  io_detail::LineReader lines(data, name);
  std::string_view line;
  if (!next_content_line(lines, line)) fail(name, lines.line_number(), "empty file (no OFF header)");

  io_detail::Tokens tokens(line);
  std::string_view keyword;
  tokens.next(keyword);
  Header header;
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
  std::size_t dim = 3;
  if (header.has_dim) {
    const std::uint64_t d = header_value("dimension");
    if (d != 3) lines.fail(fmt::format("only 3-dimensional nOFF files are supported (dimension {})", d));
    dim = 3;
  }
  const std::uint64_t nv = header_value("vertex count");
  const std::uint64_t nf = header_value("face count");
  if (nv > io_detail::kMaxElements) lines.fail(fmt::format("vertex count {} is too large", nv));
  if (nf > io_detail::kMaxElements) lines.fail(fmt::format("face count {} is too large", nf));
  if (nv == 0) lines.fail("no vertices (vertex count is 0)");
  if (nf == 0) lines.fail("no faces (face count is 0)");
  const std::size_t coords = dim + (header.homogeneous ? 1 : 0);

  TriangleSoup soup;
  soup.positions.reserve(io_detail::capped_reserve(nv, lines.remaining(), 2 * coords));
  for (std::uint64_t i = 0; i < nv; ++i) {
    if (!next_content_line(lines, line))
      lines.fail(fmt::format("unexpected end of file: header declares {} vertices, found {}", nv, i));
    tokens = io_detail::Tokens(line);
    double c[4] = {0, 0, 0, 1};
    for (std::size_t k = 0; k < coords; ++k) {
      std::string_view tok;
      if (!tokens.next(tok)) lines.fail(fmt::format("vertex {} has fewer than {} coordinates", i, coords));
      if (!io_detail::parse_double(tok, c[k]))
        lines.fail(fmt::format("vertex {}: invalid coordinate {}", i, quote(tok)));
      if (!std::isfinite(c[k])) lines.fail(fmt::format("vertex {} has a non-finite coordinate {}", i, quote(tok)));
    }
    if (header.homogeneous) {
      if (c[3] == 0.0) lines.fail(fmt::format("vertex {} has homogeneous coordinate w = 0", i));
      for (int k = 0; k < 3; ++k) c[k] /= c[3];
      if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2]))
        lines.fail(fmt::format("vertex {} is not finite after dividing by w", i));
    }
    soup.positions.emplace_back(c[0], c[1], c[2]);
  }

  io_detail::FanCounter fan;
  std::vector<int> poly;
  soup.faces.reserve(io_detail::capped_reserve(nf, lines.remaining(), 8));
  for (std::uint64_t f = 0; f < nf; ++f) {
    if (!next_content_line(lines, line))
      lines.fail(fmt::format("unexpected end of file: header declares {} faces, found {}", nf, f));
    tokens = io_detail::Tokens(line);
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
    fan.add(poly, soup.faces);  // any colour after the indices is ignored
  }
  if (next_content_line(lines, line))
    warnings.push_back(fmt::format("{}:{}: data after the last face ignored", name, lines.line_number()));
  fan.warn(warnings);
  return soup;
}

std::string write_off(const TriangleSoup& soup) {
  io_detail::check_soup_for_writing(soup);
  std::string out;
  out.reserve(soup.positions.size() * 64 + soup.faces.size() * 32 + 64);
  out += "OFF\n";
  io_detail::append_number(out, static_cast<std::int64_t>(soup.positions.size()));
  out += ' ';
  io_detail::append_number(out, static_cast<std::int64_t>(soup.faces.size()));
  out += " 0\n";
  io_detail::append_ascii_vertices_and_faces(out, soup);
  return out;
}

}  // namespace freeform
