// Whole-file reading and atomic writing.
#pragma once

#include <string>
#include <string_view>

namespace freeform {

// The whole file; IoError naming the file if it cannot be opened or read.
std::string read_file(const std::string& path);

// Writes `data` to a temporary file next to `path`, flushes it, then renames it over `path`.
// On any failure the temporary is removed, `path` is untouched and IoError is thrown.
void write_file_atomic(const std::string& path, std::string_view data);

}  // namespace freeform
