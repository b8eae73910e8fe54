#include "freeform/io/mesh_io.h"

#include "freeform/common/error.h"
#include "freeform/io/file_util.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <filesystem>

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
    throw InvalidInput(fmt::format("unknown mesh format '{}' (expected obj, off, ply or stl)", name));
  return format;
}

MeshFormat format_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  if (!ext.empty() && ext[0] == '.') ext.erase(0, 1);
  MeshFormat format{};
  if (ext.empty() || !try_parse_format(ext, format))
    throw IoError(path, 0,
                  "unknown mesh file extension (expected .obj, .off, .ply or .stl, or give the format explicitly)");
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
  }
  return "unknown";
}

ReadResult read_mesh(const std::string& path, const ReadOptions& options) {
  const MeshFormat format = resolve(options.format, path);
  const std::string data = read_file(path);
  ReadResult result;
  switch (format) {
    case MeshFormat::Obj:
      result.soup = read_obj(data, path, result.warnings);
      break;
    case MeshFormat::Off:
      result.soup = read_off(data, path, result.warnings);
      break;
    case MeshFormat::Ply:
      result.soup = read_ply(data, path, result.warnings);
      break;
    case MeshFormat::Stl:
      result.soup = read_stl(data, path, result.warnings);
      break;
    case MeshFormat::Auto:
      FF_CHECK(false, "format not resolved");
  }
  return result;
}

void write_mesh(const std::string& path, const TriangleSoup& soup, const WriteOptions& options) {
  write_file_atomic(path, mesh_bytes(path, soup, options));
}

std::string mesh_bytes(const std::string& path, const TriangleSoup& soup, const WriteOptions& options) {
  const MeshFormat format = resolve(options.format, path);
  // Never write what the readers refuse: a non-finite coordinate, or one beyond STL's floats.
  const double limit = format == MeshFormat::Stl ? double(std::numeric_limits<float>::max())
                                                 : std::numeric_limits<double>::max();
  for (std::size_t v = 0; v < soup.positions.size(); ++v)
    for (const double c : soup.positions[v])
      if (!(std::abs(c) <= limit))
        throw InvalidInput(path + ": cannot write vertex " + std::to_string(v) + ": its coordinate " +
                           fmt::format("{}", c) +
                           (std::isfinite(c) ? " is beyond the single precision of STL" : " is not finite"));
  std::string data;
  switch (format) {
    case MeshFormat::Obj:
      data = write_obj(soup);
      break;
    case MeshFormat::Off:
      data = write_off(soup);
      break;
    case MeshFormat::Ply:
      data = write_ply(soup, options.binary);
      break;
    case MeshFormat::Stl:
      data = write_stl(soup, options.binary);
      break;
    case MeshFormat::Auto:
      FF_CHECK(false, "format not resolved");
  }
  return data;
}

}  // namespace freeform
