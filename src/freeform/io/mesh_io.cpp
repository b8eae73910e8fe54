#include "freeform/io/mesh_io.h"

#include "freeform/common/error.h"
#include "freeform/io/file_util.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>

namespace freeform {
namespace {

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool try_parse_format(std::string_view name, MeshFormat& out) {
  const std::string n = lower(name);
  if (n == "obj")
    out = MeshFormat::Obj;
  else if (n == "off")
    out = MeshFormat::Off;
  else if (n == "ply")
    out = MeshFormat::Ply;
  else if (n == "stl")
    out = MeshFormat::Stl;
  else if (n == "gltf" || n == "glb")
    out = MeshFormat::Gltf;
  else
    return false;
  return true;
}

MeshFormat resolve(MeshFormat requested, const std::string& path) {
  return requested == MeshFormat::Auto ? format_from_path(path) : requested;
}

}  // namespace

MeshFormat parse_mesh_format(std::string_view name) {
  MeshFormat format{};
  if (!try_parse_format(name, format))
    throw InvalidInput(fmt::format("unknown mesh format '{}' (expected obj, off, ply, stl, gltf or glb)", name));
  return format;
}

MeshFormat format_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  MeshFormat format{};
  if (ext.empty() || !try_parse_format(ext, format))
    throw IoError(path, 0,
                  "unknown mesh file extension (expected .obj, .off, .ply, .stl, .gltf or .glb, or give the format explicitly)");
  return format;
}

const char* format_name(MeshFormat format) {
  switch (format) {
    case MeshFormat::Auto:
      return "auto";
    case MeshFormat::Obj:
      return "obj";
    case MeshFormat::Off:
      return "off";
    case MeshFormat::Ply:
      return "ply";
    case MeshFormat::Stl:
      return "stl";
    case MeshFormat::Gltf:
      return "gltf";
  }
  return "unknown";
}

ReadResult read_mesh(const std::string& path, const ReadOptions& options) {
  const MeshFormat format = resolve(options.format, path);
  ReadResult result;
  result.bytes = std::make_shared<const std::string>(read_file(path));
  const std::string& data = *result.bytes;
  switch (format) {
    case MeshFormat::Obj:
      read_obj(data, path, result);
      break;
    case MeshFormat::Off:
      read_off(data, path, result);
      break;
    case MeshFormat::Ply:
      read_ply(data, path, result);
      break;
    case MeshFormat::Stl:
      read_stl(data, path, result);
      break;
    case MeshFormat::Gltf:
      read_gltf(data, path, result);
      break;
    case MeshFormat::Auto:
      FF_CHECK(false, "format not resolved");
  }
  result.bytes.reset();
  return result;
}

std::shared_ptr<const std::string> file_bytes(std::string_view data, const ReadResult& out) {
  if (out.bytes && out.bytes->data() == data.data() && out.bytes->size() == data.size()) return out.bytes;
  return std::make_shared<const std::string>(data);
}

namespace {

// Never write what the readers refuse: a non-finite coordinate, or one beyond STL's floats.
void check_positions(const std::string& path, MeshFormat format, std::span<const Vec3> positions) {
  const double limit = format == MeshFormat::Stl ? double(std::numeric_limits<float>::max())
                                                 : std::numeric_limits<double>::max();
  for (std::size_t v = 0; v < positions.size(); ++v)
    for (const double c : positions[v])
      if (!(std::abs(c) <= limit))
        throw InvalidInput(path + ": cannot write vertex " + std::to_string(v) + ": its coordinate " +
                           fmt::format("{}", c) +
                           (std::isfinite(c) ? " is beyond the single precision of STL" : " is not finite"));
}

// Vertices of faces that share their single-precision position with an earlier one. STL and
// glTF store coordinates as floats and their readers weld corners at equal positions (weld.h),
// so such vertices come back as one: a repaired file's split copies, or points closer than a
// float's precision.
std::size_t vertices_welded_on_reading(const TriangleSoup& soup) {
  std::vector<char> used(soup.positions.size(), 0);
  for (const auto& f : soup.faces)
    for (const int v : f) used[static_cast<std::size_t>(v)] = 1;
  // The float bits, -0 as +0 (the readers weld both).
  const auto bits = [](double c) { return std::bit_cast<std::uint32_t>(static_cast<float>(c) + 0.0f); };
  std::vector<std::array<std::uint32_t, 3>> keys;
  for (std::size_t v = 0; v < soup.positions.size(); ++v)
    if (used[v])
      keys.push_back({bits(soup.positions[v].x()), bits(soup.positions[v].y()), bits(soup.positions[v].z())});
  std::sort(keys.begin(), keys.end());
  return static_cast<std::size_t>(keys.end() - std::unique(keys.begin(), keys.end()));
}

bool has_extension(const std::string& path, std::string_view ext) {
  return lower(std::filesystem::path(path).extension().string()) == ext;
}

// A new file of `format` from the soup and what it can hold of the attributes.
std::string new_file(MeshFormat format, const std::string& path, const TriangleSoup& soup, const MeshAttributes& a,
                     std::optional<bool> binary, std::vector<std::string>& dropped) {
  if (format == MeshFormat::Stl || format == MeshFormat::Gltf)
    if (const std::size_t n = vertices_welded_on_reading(soup); n > 0)
      dropped.push_back(
          fmt::format("separate vertices at equal positions: {} ({}'s reader joins them; OBJ, OFF and PLY "
                      "keep them apart)",
                      n, format == MeshFormat::Stl ? "STL" : "glTF"));
  switch (format) {
    case MeshFormat::Obj:
      return write_obj(soup, a, dropped);
    case MeshFormat::Off:
      return write_off(soup, a, dropped);
    case MeshFormat::Ply:
      return write_ply(soup, binary.value_or(true), a, dropped);
    case MeshFormat::Gltf:
      return write_gltf(soup, binary.value_or(has_extension(path, ".glb")), a, dropped);
    case MeshFormat::Stl: {
      const bool polygons = a.polygons.size() > 0 && a.polygons.corners.size() != 3 * static_cast<std::size_t>(a.polygons.size());
      if (polygons) dropped.push_back("polygons (STL holds triangles)");
      if (!a.uv.empty()) dropped.push_back("texture coordinates (STL has none)");
      if (!a.normal.empty()) dropped.push_back("vertex normals (STL has facet normals only)");
      for (const NamedAttribute& v : a.vertex) dropped.push_back(fmt::format("vertex property '{}' (STL has none)", v.name));
      for (const NamedAttribute& f : a.face) dropped.push_back(fmt::format("face property '{}' (STL has none)", f.name));
      return write_stl(soup, binary.value_or(true));
    }
    case MeshFormat::Auto:
      break;
  }
  FF_CHECK(false, "format not resolved");
  return {};
}

}  // namespace

MeshBytes mesh_bytes(const std::string& path, const ReadResult& file, std::span<const Vec3> positions,
                     const WriteOptions& options) {
  const MeshFormat format = resolve(options.format, path);
  if (positions.size() != file.soup.positions.size())
    throw InvalidInput(fmt::format("{}: {} positions given for a mesh of {} vertices", path, positions.size(),
                                   file.soup.positions.size()));
  check_positions(path, format, positions);
  MeshBytes out;
  // A read glTF is always rewritten: its source writes either container (.gltf or .glb, by the
  // path's extension).
  const bool same_encoding = format == MeshFormat::Gltf || !options.binary || (file.source && *options.binary == file.source->binary());
  if (file.source && format == file.format && same_encoding) {
    out.data = file.source->rewrite(file, positions, out.companions, path);
    return out;
  }
  TriangleSoup soup{{positions.begin(), positions.end()}, file.soup.faces};
  MeshAttributes attributes = file.attributes;
  attributes.normal.values = recomputed_normals(attributes.polygons, attributes.normal, positions, file.soup.positions);
  out.data = new_file(format, path, soup, attributes, options.binary, out.dropped);
  if (file.source && !file.source->kept_only_by_rewrite().empty())
    out.dropped.push_back(file.source->kept_only_by_rewrite() + fmt::format(" (only kept when writing {} again)", format_name(file.format)));
  return out;
}

std::vector<std::string> write_mesh(const std::string& path, const ReadResult& file, std::span<const Vec3> positions,
                                    const WriteOptions& options) {
  MeshBytes bytes = mesh_bytes(path, file, positions, options);
  for (const auto& f : prepare_mesh_files(path, bytes)) f->commit();
  return bytes.dropped;
}

std::vector<std::unique_ptr<PreparedFile>> prepare_mesh_files(const std::string& path, const MeshBytes& bytes) {
  const std::filesystem::path folder = std::filesystem::path(path).parent_path();
  std::vector<std::unique_ptr<PreparedFile>> files;
  for (const auto& [name, data] : bytes.companions)
    files.push_back(std::make_unique<PreparedFile>((folder / name).string(), data));
  files.push_back(std::make_unique<PreparedFile>(path, bytes.data));
  return files;
}

void write_mesh(const std::string& path, const TriangleSoup& soup, const WriteOptions& options) {
  write_file_atomic(path, mesh_bytes(path, soup, options));
}

std::string mesh_bytes(const std::string& path, const TriangleSoup& soup, const WriteOptions& options) {
  const MeshFormat format = resolve(options.format, path);
  check_positions(path, format, soup.positions);
  std::vector<std::string> dropped;
  return new_file(format, path, soup, MeshAttributes{}, options.binary, dropped);
}

}  // namespace freeform
