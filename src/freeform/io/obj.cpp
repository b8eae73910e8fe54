// Wavefront OBJ: `v` and `f` statements; everything else is ignored.
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"

#include <fmt/format.h>

#include <cmath>

namespace freeform {
namespace {

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

// A positive index that refers past the vertices seen so far; checked once the file is read.
struct ForwardRef {
  std::size_t line;
  std::size_t face;
  long long index;
};

}  // namespace

TriangleSoup read_obj(std::string_view data, const std::string& name, std::vector<std::string>& warnings) {
  using io_detail::fail;
  if (data.empty()) fail(name, 0, "empty file");
  io_detail::LineReader lines(data, name);
  TriangleSoup soup;
  io_detail::FanCounter fan;
  std::vector<int> poly;
  std::vector<ForwardRef> forward;
  std::string joined;
  std::size_t face_count = 0;

  std::string_view line;
  while (lines.next(line)) {
    const std::size_t line_no = lines.line_number();
    if (continues(line) && !is_comment(line)) {
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
    io_detail::Tokens tokens(line);
    std::string_view keyword;
    if (!tokens.next(keyword)) continue;

    if (keyword == "v") {
      if (soup.positions.size() >= io_detail::kMaxElements) fail(name, line_no, "too many vertices");
      double xyz[3];
      for (double& c : xyz) {
        std::string_view tok;
        if (!tokens.next(tok))
          fail(name, line_no, fmt::format("vertex {} has fewer than 3 coordinates", soup.positions.size()));
        if (!io_detail::parse_double(tok, c))
          fail(name, line_no, fmt::format("vertex {}: invalid coordinate {}", soup.positions.size(), quote(tok)));
        if (!std::isfinite(c))
          fail(name, line_no,
               fmt::format("vertex {} has a non-finite coordinate {}", soup.positions.size(), quote(tok)));
      }
      soup.positions.emplace_back(xyz[0], xyz[1], xyz[2]);
    } else if (keyword == "f") {
      poly.clear();
      const auto nverts = static_cast<long long>(soup.positions.size());
      std::string_view tok;
      while (tokens.next(tok) && tok[0] != '#') {
        const std::string_view head = tok.substr(0, tok.find('/'));
        long long index = 0;
        if (!io_detail::parse_int(head, index))
          fail(name, line_no, fmt::format("face {}: invalid vertex index {}", face_count, quote(tok)));
        if (index == 0)
          fail(name, line_no, fmt::format("face {}: vertex index 0 is invalid (OBJ indices start at 1)", face_count));
        if (index < 0) {
          if (-index > nverts)
            fail(name, line_no,
                 fmt::format("face {}: relative vertex index {} reaches before the first vertex ({} vertices so far)",
                             face_count, index, nverts));
          poly.push_back(static_cast<int>(nverts + index));
        } else {
          if (static_cast<unsigned long long>(index) > io_detail::kMaxElements)
            fail(name, line_no, fmt::format("face {}: vertex index {} out of range", face_count, index));
          if (index > nverts) forward.push_back({line_no, face_count, index});
          poly.push_back(static_cast<int>(index - 1));
        }
      }
      if (poly.size() < 3)
        fail(name, line_no, fmt::format("face {} has {} vertices (at least 3 needed)", face_count, poly.size()));
      fan.add(poly, soup.faces);
      ++face_count;
    }
    // vn, vt, vp, g, o, s, usemtl, mtllib, l, p, comments, ...: ignored.
  }

  const auto nverts = static_cast<long long>(soup.positions.size());
  for (const ForwardRef& ref : forward) {
    if (ref.index > nverts)
      fail(name, ref.line,
           fmt::format("face {}: vertex index {} out of range (file has {} vertices)", ref.face, ref.index, nverts));
  }
  io_detail::require_nonempty(soup, name);
  fan.warn(warnings);
  return soup;
}

std::string write_obj(const TriangleSoup& soup) {
  io_detail::check_soup_for_writing(soup);
  std::string out;
  out.reserve(soup.positions.size() * 64 + soup.faces.size() * 32 + 64);
  out += "# freeform: ";
  io_detail::append_number(out, static_cast<std::int64_t>(soup.positions.size()));
  out += " vertices, ";
  io_detail::append_number(out, static_cast<std::int64_t>(soup.faces.size()));
  out += " triangles\n";
  for (const Vec3& p : soup.positions) {
    out += 'v';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      io_detail::append_number(out, p[k]);
    }
    out += '\n';
  }
  for (const Tri& f : soup.faces) {
    out += 'f';
    for (int v : f) {
      out += ' ';
      io_detail::append_number(out, static_cast<std::int64_t>(v) + 1);
    }
    out += '\n';
  }
  return out;
}

}  // namespace freeform
