// Internal: rewriting a text mesh file with new numbers in place (the positions and normals of
// OBJ, OFF and ascii PLY), everything else copied byte for byte.
#pragma once

#include "freeform/io/mesh_attributes.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace freeform::io_detail {

// The bytes [begin, end) of a file that hold a row of numbers ("x y z").
struct TextSpan {
  std::size_t begin = 0, end = 0;
};

// A span whose `width` numbers become `values`; when `old` (the values read) equals `values`
// the file's text is kept as written.
struct NumberRun {
  std::size_t begin = 0, end = 0;
  const double* values = nullptr;
  const double* old = nullptr;
  int width = 3;
};

// `data` with every run replaced (runs sorted by begin, not overlapping), numbers written in
// their shortest round-trip form separated by single spaces.
std::string patch_numbers(std::string_view data, std::vector<NumberRun> runs);

// Runs for rows of 3 values: span i becomes values[3i..3i+3), kept where old[3i..] is equal.
void add_runs(std::vector<NumberRun>& runs, const std::vector<TextSpan>& spans, const double* values,
              const double* old);

// The byte range of tokens [first, last] as offsets into `data` (the tokens are views of it).
inline TextSpan span_of(std::string_view data, std::string_view first, std::string_view last) {
  return {static_cast<std::size_t>(first.data() - data.data()),
          static_cast<std::size_t>(last.data() + last.size() - data.data())};
}

// Adjusts a rewritten text to the folder of `out_path` (OBJ: its material libraries' paths).
using Relink = std::function<std::string(std::string text, const std::string& out_path)>;

// The FileSource of a text file whose positions and normals are rows of three numbers at known
// spans (OBJ, OFF): a rewrite patches them and copies the rest, then applies `relink` if set.
// `kept_only` names what only a rewrite keeps (FileSource::kept_only_by_rewrite).
std::shared_ptr<const FileSource> make_text_source(std::shared_ptr<const std::string> data,
                                                   std::vector<TextSpan> positions, std::vector<TextSpan> normals,
                                                   std::string kept_only, Relink relink = {});

}  // namespace freeform::io_detail
