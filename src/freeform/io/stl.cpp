// STL, ascii and binary. STL stores every triangle with its own corners; the reader welds
// corners with exactly equal positions (-0.0 == 0.0) into shared vertices, numbered in order of
// first appearance.
#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"
#include "freeform/io/weld.h"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <utility>

namespace freeform {
namespace {

using io_detail::fail;
using io_detail::quote;

constexpr std::size_t kHeaderBytes = 84;
constexpr std::size_t kTriangleBytes = 50;


bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i]))) return false;
  return true;
}

bool starts_with_solid(std::string_view data) {
  std::size_t i = 0;
  while (i < data.size() && (io_detail::is_space(data[i]) || data[i] == '\n')) ++i;
  return data.size() - i >= 5 && iequals(data.substr(i, 5), "solid");
}

std::uint32_t load_u32_le(const unsigned char* p) {
  return static_cast<std::uint32_t>(p[0]) | (static_cast<std::uint32_t>(p[1]) << 8) |
         (static_cast<std::uint32_t>(p[2]) << 16) | (static_cast<std::uint32_t>(p[3]) << 24);
}

float load_f32_le(const unsigned char* p) { return std::bit_cast<float>(load_u32_le(p)); }

TriangleSoup read_binary(std::string_view data, std::uint32_t n, const std::string& name) {
  TriangleSoup soup;
  io_detail::PositionWelder welder(soup.positions);
  welder.reserve(static_cast<std::size_t>(n) * 3 / 2);
  soup.faces.reserve(n);
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  for (std::uint32_t t = 0; t < n; ++t) {
    const unsigned char* p = bytes + kHeaderBytes + static_cast<std::size_t>(t) * kTriangleBytes + 12;  // skip normal
    Tri tri{};
    for (int c = 0; c < 3; ++c) {
      double xyz[3];
      for (int k = 0; k < 3; ++k) {
        xyz[k] = load_f32_le(p + 12 * c + 4 * k);
        if (!std::isfinite(xyz[k]))
          fail(name, 0, fmt::format("triangle {}: vertex {} has a non-finite coordinate", t, c));
      }
      tri[static_cast<std::size_t>(c)] = welder.add(Vec3(xyz[0], xyz[1], xyz[2])).first;
    }
    soup.faces.push_back(tri);
  }
  return soup;
}

TriangleSoup read_ascii(std::string_view data, const std::string& name, std::vector<std::string>& warnings) {
  io_detail::TokenReader tokens(data, 1, name);
  TriangleSoup soup;
  io_detail::PositionWelder welder(soup.positions);
  io_detail::FanCounter fan;
  std::vector<int> poly;
  auto expect = [&tokens](const char* word) {
    std::string_view tok;
    if (!tokens.next(tok)) tokens.fail(fmt::format("unexpected end of file (expected '{}')", word));
    if (!iequals(tok, word)) tokens.fail(fmt::format("expected '{}', found {}", word, quote(tok)));
  };
  expect("solid");
  tokens.skip_line();  // solid name
  std::size_t facet = 0;
  for (;;) {
    std::string_view tok;
    if (!tokens.next(tok)) tokens.fail("unexpected end of file: missing 'endsolid'");
    if (iequals(tok, "endsolid")) {
      tokens.skip_line();
      if (!tokens.next(tok)) break;
      if (!iequals(tok, "solid"))
        tokens.fail(fmt::format("expected 'solid' or end of file after 'endsolid', found {}", quote(tok)));
      tokens.skip_line();
      continue;
    }
    if (!iequals(tok, "facet")) tokens.fail(fmt::format("expected 'facet' or 'endsolid', found {}", quote(tok)));
    expect("normal");
    for (int k = 0; k < 3; ++k) {
      tok = tokens.require("a normal component");
      double ignored = 0;
      if (!io_detail::parse_double(tok, ignored))
        tokens.fail(fmt::format("facet {}: invalid normal component {}", facet, quote(tok)));
    }
    expect("outer");
    expect("loop");
    poly.clear();
    for (;;) {
      tok = tokens.require("'vertex' or 'endloop'");
      if (iequals(tok, "endloop")) break;
      if (!iequals(tok, "vertex"))
        tokens.fail(fmt::format("facet {}: expected 'vertex' or 'endloop', found {}", facet, quote(tok)));
      float xyz[3];  // STL coordinates are single precision, ascii or binary
      for (float& c : xyz) {
        tok = tokens.require("a vertex coordinate");
        double d = 0.0;  // read as double: 1e-50 is a number (it rounds to 0 in float), not a typo
        if (!io_detail::parse_double(tok, d))
          tokens.fail(fmt::format("facet {}: invalid coordinate {}", facet, quote(tok)));
        if (std::abs(d) > std::numeric_limits<float>::max())
          tokens.fail(fmt::format("facet {}: coordinate {} is beyond the single-precision range of STL (+-3.4e38)",
                                  facet, quote(tok)));
        c = static_cast<float>(d);
        if (!std::isfinite(c))
          tokens.fail(
              fmt::format("facet {}: vertex {} has a non-finite coordinate {}", facet, poly.size(), quote(tok)));
      }
      if (soup.positions.size() >= io_detail::kMaxElements) tokens.fail("too many vertices");
      poly.push_back(welder.add(Vec3(xyz[0], xyz[1], xyz[2])).first);
    }
    if (poly.size() < 3) tokens.fail(fmt::format("facet {} has {} vertices (at least 3 needed)", facet, poly.size()));
    expect("endfacet");
    fan.add(poly, soup.positions, soup.faces);
    ++facet;
  }
  fan.warn(warnings);
  return soup;
}

void append_f32(std::string& out, float v) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
  for (int i = 0; i < 4; ++i) out += static_cast<char>((bits >> (8 * i)) & 0xffu);
}

std::array<float, 3> face_normal(const TriangleSoup& soup, const Tri& f) {
  const Vec3 n =
      (soup.positions[static_cast<std::size_t>(f[1])] - soup.positions[static_cast<std::size_t>(f[0])])
          .cross(soup.positions[static_cast<std::size_t>(f[2])] - soup.positions[static_cast<std::size_t>(f[0])]);
  const double len = n.norm();
  if (!(len > 0.0) || !std::isfinite(len)) return {0.0f, 0.0f, 0.0f};
  return {static_cast<float>(n.x() / len), static_cast<float>(n.y() / len), static_cast<float>(n.z() / len)};
}

}  // namespace

void read_stl(std::string_view data, const std::string& name, ReadResult& out) {
  if (data.empty()) fail(name, 0, "empty file");
  out.format = MeshFormat::Stl;
  std::vector<std::string>& warnings = out.warnings;
  TriangleSoup& soup = out.soup;
  bool binary_size = false;
  std::uint32_t n = 0;
  if (data.size() >= kHeaderBytes) {
    n = load_u32_le(reinterpret_cast<const unsigned char*>(data.data()) + 80);
    binary_size = data.size() - kHeaderBytes == static_cast<std::uint64_t>(n) * kTriangleBytes;
  }
  if (binary_size) {
    soup = read_binary(data, n, name);
  } else if (starts_with_solid(data)) {
    soup = read_ascii(data, name, warnings);
  } else if (data.size() < kHeaderBytes) {
    fail(name, 0,
         fmt::format("not an STL file: {} bytes is too small for a binary STL and it does not start with 'solid'",
                     data.size()));
  } else {
    const std::uint64_t room = (data.size() - kHeaderBytes) / kTriangleBytes;
    fail(name, 0,
         fmt::format("binary STL size mismatch: header declares {} triangles ({} bytes) but the file has {} bytes "
                     "(room for {} triangles)",
                     n, kHeaderBytes + static_cast<std::uint64_t>(n) * kTriangleBytes, data.size(), room));
  }
  if (soup.faces.empty()) fail(name, 0, "no faces");
}

std::string write_stl(const TriangleSoup& soup, bool binary) {
  io_detail::check_soup_for_writing(soup);
  if (binary) {
    if (soup.faces.size() > std::numeric_limits<std::uint32_t>::max())
      throw InvalidInput("cannot write binary STL: more than 2^32-1 triangles");
    std::string out(80, ' ');
    const std::string_view title = "binary STL written by freeform";
    out.replace(0, title.size(), title);
    out.reserve(kHeaderBytes + soup.faces.size() * kTriangleBytes);
    const auto n = static_cast<std::uint32_t>(soup.faces.size());
    for (int i = 0; i < 4; ++i) out += static_cast<char>((n >> (8 * i)) & 0xffu);
    for (const Tri& f : soup.faces) {
      for (float c : face_normal(soup, f)) append_f32(out, c);
      for (int v : f)
        for (int k = 0; k < 3; ++k) append_f32(out, static_cast<float>(soup.positions[static_cast<std::size_t>(v)][k]));
      out += '\0';
      out += '\0';
    }
    return out;
  }
  std::string out = "solid freeform\n";
  out.reserve(soup.faces.size() * 256 + 64);
  for (const Tri& f : soup.faces) {
    out += "  facet normal";
    for (float c : face_normal(soup, f)) {
      out += ' ';
      io_detail::append_number(out, c);
    }
    out += "\n    outer loop\n";
    for (int v : f) {
      out += "      vertex";
      for (int k = 0; k < 3; ++k) {
        out += ' ';
        io_detail::append_number(out, static_cast<float>(soup.positions[static_cast<std::size_t>(v)][k]));
      }
      out += '\n';
    }
    out += "    endloop\n  endfacet\n";
  }
  out += "endsolid freeform\n";
  return out;
}

}  // namespace freeform
