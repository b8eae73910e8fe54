#include "freeform/io/text_patch.h"

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

}  // namespace freeform::io_detail
