#include "freeform/io/text_scan.h"
#include "freeform/io/triangulate.h"

#include <fmt/format.h>

#include <cstring>

namespace freeform::io_detail {

void fail(const std::string& name, std::size_t line, const std::string& message) { throw IoError(name, line, message); }

std::string quote(std::string_view token) {
  constexpr std::size_t kMax = 24;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMax; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (token.size() > kMax) out += "...";
  return out + "'";
}

LineReader::LineReader(std::string_view data, const std::string& name) : data_(data), name_(name) {
  if (data_.size() >= 3 && std::memcmp(data_.data(), "\xEF\xBB\xBF", 3) == 0) pos_ = 3;
}

bool LineReader::next(std::string_view& line) {
  if (pos_ >= data_.size()) return false;
  ++line_;
  const char* begin = data_.data() + pos_;
  const char* end = data_.data() + data_.size();
  const char* p = begin;
  for (; p != end && *p != '\n'; ++p) {
    if (is_binary_byte(*p))
      io_detail::fail(name_, line_, fmt::format("binary data at line {} (not a text file?)", line_));
  }
  std::size_t len = static_cast<std::size_t>(p - begin);
  pos_ += len + (p != end ? 1 : 0);
  if (len > 0 && begin[len - 1] == '\r') --len;
  line = std::string_view(begin, len);
  return true;
}

bool TokenReader::next(std::string_view& token) {
  const std::size_t n = data_.size();
  while (pos_ < n) {
    const char c = data_[pos_];
    if (c == '\n') {
      ++line_;
    } else if (!is_space(c)) {
      if (is_binary_byte(c))
        io_detail::fail(name_, line_, fmt::format("binary data at line {} (not a text file?)", line_));
      break;
    }
    ++pos_;
  }
  if (pos_ >= n) {
    token_line_ = line_;
    return false;
  }
  const std::size_t start = pos_;
  while (pos_ < n && data_[pos_] != '\n' && !is_space(data_[pos_])) {
    if (is_binary_byte(data_[pos_]))
      io_detail::fail(name_, line_, fmt::format("binary data at line {} (not a text file?)", line_));
    ++pos_;
  }
  token_line_ = line_;
  token = data_.substr(start, pos_ - start);
  return true;
}

void TokenReader::skip_line() {
  while (pos_ < data_.size() && data_[pos_] != '\n') {
    if (is_binary_byte(data_[pos_]))
      io_detail::fail(name_, line_, fmt::format("binary data at line {} (not a text file?)", line_));
    ++pos_;
  }
}

std::string_view TokenReader::require(const char* what) {
  std::string_view token;
  if (!next(token)) fail(fmt::format("unexpected end of file (expected {})", what));
  return token;
}

void FanCounter::add(const std::vector<int>& poly, std::span<const Vec3> positions, std::vector<Tri>& faces,
                     MeshAttributes* attributes) {
  if (attributes != nullptr) {
    const int polygon = attributes->polygons.size();
    attributes->polygons.add(poly);
    attributes->triangle_polygon.insert(attributes->triangle_polygon.end(), poly.size() - 2, polygon);
  }
  const Cut cut = triangulate_polygon(poly, positions, faces);
  stripped += cut == Cut::Strip ? 1 : 0;
  clipped += cut == Cut::Ears ? 1 : 0;
  if (poly.size() > 3) {
    ++polygons;
    triangles += poly.size() - 2;
  }
}

void FanCounter::warn(std::vector<std::string>& warnings) const {
  if (polygons == 0) return;
  const std::string plural = polygons == 1 ? "" : "s";
  if (stripped == 0 && clipped == 0) {
    warnings.push_back(fmt::format("{} polygon{} with more than 3 vertices fan-triangulated into {} triangles",
                                   polygons, plural, triangles));
    return;
  }
  std::vector<std::string> how;
  if (stripped > 0)
    how.push_back(fmt::format("{} convex one{} of more than {} corners cut into strips", stripped,
                              stripped == 1 ? "" : "s", kFanCorners));
  if (clipped > 0) how.push_back(fmt::format("{} non-convex one{} by ear clipping", clipped, clipped == 1 ? "" : "s"));
  how.push_back(stripped + clipped == polygons ? "none fanned" : "the others fanned");
  warnings.push_back(fmt::format("{} polygon{} with more than 3 vertices triangulated into {} triangles ({})", polygons,
                                 plural, triangles, fmt::join(how, ", ")));
}

void require_nonempty(const TriangleSoup& soup, const std::string& name) {
  if (soup.positions.empty()) fail(name, 0, "no vertices");
  if (soup.faces.empty()) fail(name, 0, "no faces");
}

void check_soup_for_writing(const TriangleSoup& soup) {
  const auto n = static_cast<long long>(soup.positions.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    for (int v : soup.faces[f]) {
      if (v < 0 || v >= n)
        throw InvalidInput(
            fmt::format("cannot write mesh: face {} has vertex index {} out of range ({} vertices)", f, v, n));
    }
  }
}

void append_number(std::string& out, double value) {
  char buf[32];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  FF_CHECK(ec == std::errc(), "to_chars(double) failed");
  out.append(buf, ptr);
}

void append_number(std::string& out, float value) {
  char buf[32];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  FF_CHECK(ec == std::errc(), "to_chars(float) failed");
  out.append(buf, ptr);
}

void append_number(std::string& out, std::int64_t value) {
  char buf[24];
  auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), value);
  FF_CHECK(ec == std::errc(), "to_chars(int) failed");
  out.append(buf, ptr);
}

void append_ascii_vertices_and_faces(std::string& out, const TriangleSoup& soup) {
  for (const Vec3& p : soup.positions) {
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out += ' ';
      append_number(out, p[k]);
    }
    out += '\n';
  }
  for (const Tri& f : soup.faces) {
    out += '3';
    for (int v : f) {
      out += ' ';
      append_number(out, static_cast<std::int64_t>(v));
    }
    out += '\n';
  }
}

}  // namespace freeform::io_detail
