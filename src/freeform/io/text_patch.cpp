#include "freeform/io/text_patch.h"

#include "freeform/io/mesh_io.h"
#include "freeform/io/text_scan.h"

#include <algorithm>
#include <cstdint>

namespace freeform::io_detail {

std::string patch_numbers(std::string_view data, std::vector<NumberRun> runs) {
  std::sort(runs.begin(), runs.end(), [](const NumberRun& a, const NumberRun& b) { return a.begin < b.begin; });
  std::string out;
  out.reserve(data.size() + data.size() / 4);
  std::size_t pos = 0;
  for (const NumberRun& r : runs) {
    out.append(data.substr(pos, r.begin - pos));
    if (r.old != nullptr && std::equal(r.values, r.values + r.width, r.old)) {
      out.append(data.substr(r.begin, r.end - r.begin));
    } else {
      for (int k = 0; k < r.width; ++k) {
        if (k > 0) out += ' ';
        append_number(out, r.values[k]);
      }
    }
    pos = r.end;
  }
  out.append(data.substr(pos));
  return out;
}

void add_runs(std::vector<NumberRun>& runs, const std::vector<TextSpan>& spans, const double* values,
              const double* old) {
  for (std::size_t i = 0; i < spans.size(); ++i)
    runs.push_back({spans[i].begin, spans[i].end, values + 3 * i, old + 3 * i, 3});
}

namespace {

class TextSource final : public FileSource {
 public:
  TextSource(std::shared_ptr<const std::string> data, std::vector<TextSpan> positions, std::vector<TextSpan> normals,
             std::string kept_only, Relink relink)
      : data_(std::move(data)),
        positions_(std::move(positions)),
        normals_(std::move(normals)),
        kept_only_(std::move(kept_only)),
        relink_(std::move(relink)) {}

  std::string kept_only_by_rewrite() const override { return kept_only_; }

  std::string rewrite(const ReadResult& file, std::span<const Vec3> positions,
                      std::vector<std::pair<std::string, std::string>>&, const std::string& out_path) const override {
    const std::vector<double> normals =
        recomputed_normals(file.attributes.polygons, file.attributes.normal, positions, file.soup.positions);
    std::vector<NumberRun> runs;
    runs.reserve(positions_.size() + normals_.size());
    add_runs(runs, positions_, positions.data()->data(), file.soup.positions.data()->data());
    add_runs(runs, normals_, normals.data(), file.attributes.normal.values.data());
    std::string text = patch_numbers(*data_, std::move(runs));
    return relink_ ? relink_(std::move(text), out_path) : text;
  }

 private:
  std::shared_ptr<const std::string> data_;  // the file, shared with read_mesh's buffer
  std::vector<TextSpan> positions_;           // one per vertex
  std::vector<TextSpan> normals_;             // one per normal row
  std::string kept_only_;
  Relink relink_;
};

}  // namespace

std::shared_ptr<const FileSource> make_text_source(std::shared_ptr<const std::string> data,
                                                   std::vector<TextSpan> positions, std::vector<TextSpan> normals,
                                                   std::string kept_only, Relink relink) {
  return std::make_shared<TextSource>(std::move(data), std::move(positions), std::move(normals), std::move(kept_only),
                                      std::move(relink));
}

}  // namespace freeform::io_detail
