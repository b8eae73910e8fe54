// Reading and writing triangle meshes: OBJ, OFF, PLY (ascii / binary), STL (ascii / binary).
// Readers return the soup in file vertex order; polygons are fan-triangulated (with a
// warning). Every failure is an IoError naming the file and, for text formats, the line.
// Writes are atomic: a temporary file in the target folder, renamed over the target.
#pragma once

#include "freeform/mesh/types.h"

#include <string>
#include <string_view>
#include <vector>

namespace freeform {

enum class MeshFormat { Auto, Obj, Off, Ply, Stl };

// "obj", "off", "ply", "stl" (case-insensitive) -> format; throws InvalidInput otherwise.
MeshFormat parse_mesh_format(std::string_view name);
// From the file extension; throws IoError naming the file if it has no known extension.
MeshFormat format_from_path(const std::string& path);
const char* format_name(MeshFormat format);

struct ReadOptions {
  MeshFormat format = MeshFormat::Auto;  // Auto: by extension
};

struct ReadResult {
  TriangleSoup soup;
  std::vector<std::string> warnings;  // e.g. "12 polygons fan-triangulated into 36 triangles"
};

ReadResult read_mesh(const std::string& path, const ReadOptions& options = {});

struct WriteOptions {
  MeshFormat format = MeshFormat::Auto;  // Auto: by extension
  bool binary = true;                    // PLY and STL: binary (little endian) or ascii
};

void write_mesh(const std::string& path, const TriangleSoup& soup, const WriteOptions& options = {});
// The bytes write_mesh would write (format from options or the extension of `path`).
std::string mesh_bytes(const std::string& path, const TriangleSoup& soup, const WriteOptions& options = {});

// Format-level entry points on in-memory data (used by read_mesh / write_mesh and the fuzzers).
// `name` is only used in error messages.
TriangleSoup read_obj(std::string_view data, const std::string& name, std::vector<std::string>& warnings);
TriangleSoup read_off(std::string_view data, const std::string& name, std::vector<std::string>& warnings);
TriangleSoup read_ply(std::string_view data, const std::string& name, std::vector<std::string>& warnings);
TriangleSoup read_stl(std::string_view data, const std::string& name, std::vector<std::string>& warnings);
std::string write_obj(const TriangleSoup& soup);
std::string write_off(const TriangleSoup& soup);
std::string write_ply(const TriangleSoup& soup, bool binary);
std::string write_stl(const TriangleSoup& soup, bool binary);

}  // namespace freeform
