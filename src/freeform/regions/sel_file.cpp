#include "freeform/regions/sel_file.h"

#include "freeform/common/error.h"
#include "freeform/io/file_util.h"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace freeform {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits data into lines, 1-based line numbers, '\r' before '\n' dropped.
class Lines {
 public:
  explicit Lines(std::string_view data) : data_(data) {
    if (data_.starts_with("\xEF\xBB\xBF")) data_.remove_prefix(3);
  }
  bool next(std::string_view& line) {
    if (pos_ >= data_.size()) return false;
    const std::size_t end = data_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? data_.size() : end;
    line = data_.substr(pos_, stop - pos_);
    pos_ = stop + 1;
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }

 private:
  std::string_view data_;
  std::size_t pos_ = 0;
  std::size_t number_ = 0;
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

std::string shown(std::string_view token) {
  std::string out = "\"";
  for (std::size_t i = 0; i < token.size() && i < 24; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    out += c >= 0x20 && c < 0x7f ? static_cast<char>(c) : '?';
  }
  if (token.size() > 24) out += "...";
  return out + "\"";
}

bool next_token(std::string_view& rest, std::string_view& token) {
  std::size_t i = 0;
  while (i < rest.size() && is_space(rest[i])) ++i;
  std::size_t j = i;
  while (j < rest.size() && !is_space(rest[j])) ++j;
  token = rest.substr(i, j - i);
  rest.remove_prefix(j);
  return !token.empty();
}

bool parse_double(std::string_view token, double& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  return ec == std::errc() && ptr == token.data() + token.size() && std::isfinite(value);
}

}  // namespace

std::vector<int> parse_sel(std::string_view data, const std::string& name, int n_vertices) {
  std::vector<int> labels;
  labels.reserve(static_cast<std::size_t>(std::max(n_vertices, 0)));
  Lines lines(data);
  std::string_view line;
  while (lines.next(line)) {
    line = trim(line);
    if (line.empty() || line.front() == '#') continue;
    const std::size_t n = lines.number();
    std::string_view rest = line, token, extra;
    next_token(rest, token);
    if (next_token(rest, extra))
      throw IoError(name, n, "expected one label per line, found also " + shown(extra));
    int label = -1;
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), label);
    if (ec != std::errc() || ptr != token.data() + token.size() || label < 0 || label > 2)
      throw IoError(name, n, "label " + shown(token) + " is not 0 (fixed), 1 (free) or 2 (handle)");
    if (static_cast<long long>(labels.size()) >= n_vertices)
      throw IoError(name, n, "more labels than the mesh's " + std::to_string(n_vertices) + " vertices");
    labels.push_back(label);
  }
  if (static_cast<long long>(labels.size()) != n_vertices)
    throw IoError(name, lines.number(),
                  "the file ends after " + std::to_string(labels.size()) + " labels, but the mesh has " +
                      std::to_string(n_vertices) + " vertices (one label per vertex)");
  return labels;
}

std::vector<int> read_sel_file(const std::string& path, int n_vertices) {
  return parse_sel(read_file(path), path, n_vertices);
}

Eigen::Matrix4d parse_def(std::string_view data, const std::string& name) {
  Eigen::Matrix4d m;
  int count = 0;
  Lines lines(data);
  std::string_view line;
  bool first = true;
  while (lines.next(line)) {
    line = trim(line);
    const bool is_first = first;
    first = false;
    if (line.empty() || line.front() == '#') continue;
    std::string_view rest = line, token;
    double value = 0.0;
    // The header line of the benchmark files need not start with '#': a first line that is not
    // numeric is that comment.
    if (is_first) {
      std::string_view probe = line, t;
      next_token(probe, t);
      if (!parse_double(t, value)) continue;
    }
    while (next_token(rest, token)) {
      if (!parse_double(token, value))
        throw IoError(name, lines.number(), "expected a finite number of the 4x4 matrix, found " + shown(token));
      if (count == 16) throw IoError(name, lines.number(), "more than 16 numbers: expected one 4x4 matrix");
      m(count / 4, count % 4) = value;
      ++count;
    }
  }
  if (count != 16)
    throw IoError(name, lines.number(),
                  "the file ends after " + std::to_string(count) + " numbers; expected a 4x4 matrix (16 numbers, row-major)");
  return m;
}

Eigen::Matrix4d read_def_file(const std::string& path) { return parse_def(read_file(path), path); }

}  // namespace freeform
