// Internal: an OBJ file's material libraries (`mtllib a.mtl b.mtl`) name files relative to the
// OBJ's folder. Written into another folder, those names would resolve to nothing there.
#pragma once

#include <string>

namespace freeform::io_detail {

// `text` (an OBJ file read from `in_folder`, folder_of() its path) for writing to `out_path`: in another folder each
// relative library name becomes the path from there to the same file (absolute where that path
// would hold a space, which separates names in OBJ). The libraries' own texture names resolve
// from their folder, so they keep working. Unchanged when both folders are one.
std::string relink_material_libraries(std::string text, const std::string& in_folder, const std::string& out_path);

}  // namespace freeform::io_detail
