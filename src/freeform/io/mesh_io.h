// Reading and writing meshes: OBJ, OFF, PLY (ascii / binary), STL (ascii / binary), glTF 2.0
// (.gltf / .glb). Readers return the welded triangle soup in file vertex order (polygons
// fan-triangulated, with a warning) and everything else the file held (mesh_attributes.h).
// Every failure is an IoError naming the file and, for text formats, the line.
// Writes are atomic: a temporary file in the target folder, renamed over the target.
#pragma once

#include "freeform/io/file_util.h"
#include "freeform/io/mesh_attributes.h"
#include "freeform/mesh/types.h"

#include <memory>
#include <span>

#include <string>
#include <string_view>
#include <optional>
#include <utility>
#include <vector>

namespace freeform {

enum class MeshFormat { Auto, Obj, Off, Ply, Stl, Gltf };

// "obj", "off", "ply", "stl", "gltf", "glb" (case-insensitive) -> format; throws InvalidInput otherwise.
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
  MeshFormat format = MeshFormat::Auto;
  MeshAttributes attributes;                 // polygons, UVs, normals, colours, other properties
  std::shared_ptr<const FileSource> source;  // the file itself, to write it back (null: none)
  // read_mesh's buffer of the file, lent to the reader so that its FileSource shares it instead
  // of copying it (readers call file_bytes); cleared once the reader returns.
  std::shared_ptr<const std::string> bytes;
};

// The file's content for a FileSource: `out.bytes` when `data` is that buffer, else a copy.
std::shared_ptr<const std::string> file_bytes(std::string_view data, const ReadResult& out);

ReadResult read_mesh(const std::string& path, const ReadOptions& options = {});

struct WriteOptions {
  MeshFormat format = MeshFormat::Auto;  // Auto: by extension
  // PLY and STL: binary (little endian) or ascii; unset: a file's own encoding when it is
  // written back in its format, otherwise binary. glTF: binary (.glb) by extension.
  std::optional<bool> binary;
};

void write_mesh(const std::string& path, const TriangleSoup& soup, const WriteOptions& options = {});
// The bytes write_mesh would write (format from options or the extension of `path`).
std::string mesh_bytes(const std::string& path, const TriangleSoup& soup, const WriteOptions& options = {});

// A file as read, written with new positions (one per soup vertex). In its own format and
// encoding (glTF: either container, .gltf or .glb) the file itself is rewritten (FileSource):
// everything but the positions and normals byte for byte. Another format gets what it can
// hold; `dropped` says what it could not.
struct MeshBytes {
  std::string data;
  std::vector<std::pair<std::string, std::string>> companions;  // (path, bytes) beside it
  std::vector<std::string> dropped;  // e.g. "texture coordinates (STL has none)"
};
MeshBytes mesh_bytes(const std::string& path, const ReadResult& file, std::span<const Vec3> positions,
                     const WriteOptions& options = {});
// The companions (beside `path`) and the file, each written to a temporary beside its target and
// not yet committed: commit them in order once everything that goes with them is prepared, so
// that a failure leaves every target as it was.
std::vector<std::unique_ptr<PreparedFile>> prepare_mesh_files(const std::string& path, const MeshBytes& bytes);
// Prepares all, then commits the companions and the file; returns what was dropped.
std::vector<std::string> write_mesh(const std::string& path, const ReadResult& file,
                                    std::span<const Vec3> positions, const WriteOptions& options = {});

// Format-level entry points on in-memory data (used by read_mesh / write_mesh and the fuzzers).
// `name` is only used in error messages.
// The readers fill soup, warnings, attributes and source of `out`.
void read_obj(std::string_view data, const std::string& name, ReadResult& out);
void read_off(std::string_view data, const std::string& name, ReadResult& out);
void read_ply(std::string_view data, const std::string& name, ReadResult& out);
void read_stl(std::string_view data, const std::string& name, ReadResult& out);
// `path` locates external buffers (.gltf); `data` is the .gltf or .glb file's content.
void read_gltf(std::string_view data, const std::string& path, ReadResult& out);
// New files from a soup and its attributes (polygons used when present); what the format
// cannot hold is appended to `dropped`.
std::string write_obj(const TriangleSoup& soup, const MeshAttributes& attributes, std::vector<std::string>& dropped);
std::string write_off(const TriangleSoup& soup, const MeshAttributes& attributes, std::vector<std::string>& dropped);
std::string write_ply(const TriangleSoup& soup, bool binary, const MeshAttributes& attributes,
                      std::vector<std::string>& dropped);
std::string write_stl(const TriangleSoup& soup, bool binary);
std::string write_gltf(const TriangleSoup& soup, bool binary, const MeshAttributes& attributes,
                       std::vector<std::string>& dropped);

}  // namespace freeform
