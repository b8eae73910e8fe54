// `freeform convert IN OUT`: rewrite a mesh in another format, optionally repaired.
#include "commands.h"

#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/repair.h"
#include "freeform/mesh/mesh.h"

#include <fmt/core.h>

#include <filesystem>
#include <memory>

namespace freeform::cli {
namespace {

struct ConvertOptions {
  std::string in, out, in_format, out_format;
  bool ascii = false, repair = false, overwrite_input = false;
};

void run(const ConvertOptions& opt) {
  ReadOptions ro;
  if (!opt.in_format.empty()) ro.format = parse_mesh_format(opt.in_format);
  WriteOptions wo;
  wo.format = opt.out_format.empty() ? format_from_path(opt.out) : parse_mesh_format(opt.out_format);
  if (opt.ascii) wo.binary = false;
  if (same_file(opt.in, opt.out) && !opt.overwrite_input)
    throw InvalidInput("output " + opt.out + " is the input file; pass --overwrite-input to replace it");

  ReadResult read = read_mesh(opt.in, ro);
  for (const auto& w : read.warnings) fmt::print(stderr, "warning: {}\n", w);
  if (opt.repair) {
    std::string lost;
    const BuildReport report = repair(read, opt.in, lost);
    for (const auto& c : report.changes) fmt::print(stderr, "repair: {}\n", c);
    if (report.changes.size() < static_cast<std::size_t>(report.dropped_faces + report.split_vertices))
      fmt::print(stderr, "repair: ... {} faces dropped, {} vertices split in all\n", report.dropped_faces,
                 report.split_vertices);
    if (!lost.empty()) fmt::print(stderr, "repair: {}\n", lost);
  }
  try {
    for (const std::string& d : write_mesh(opt.out, read, read.soup.positions, wo))
      fmt::print(stderr, "note: {} cannot hold the input's {}\n", opt.out, d);
  } catch (const Error& e) {
    throw OutputError(e.what());
  }
  fmt::print("wrote {} ({} vertices, {} faces, {})\n", opt.out, read.soup.positions.size(),
             read.attributes.polygons.size() > 0 ? read.attributes.polygons.size() : static_cast<int>(read.soup.faces.size()),
             format_name(wo.format));
}

}  // namespace

void add_convert_command(CLI::App& app) {
  auto opt = std::make_shared<ConvertOptions>();
  CLI::App* cmd = app.add_subcommand("convert", "Convert a mesh between OBJ, OFF, PLY, STL and glTF, keeping what both formats can hold");
  cmd->add_option("IN", opt->in, "Input mesh")->required();
  cmd->add_option("OUT", opt->out, "Output mesh; format from the extension")->required();
  cmd->add_option("--in-format", opt->in_format, "Input format, overriding the extension (obj|off|ply|stl|gltf)");
  cmd->add_option("--out-format", opt->out_format, "Output format, overriding the extension (obj|off|ply|stl|gltf)");
  cmd->add_flag("--ascii", opt->ascii, "Write PLY/STL as text (default: the input's encoding when converting to its own format, else binary)");
  cmd->add_flag("--repair", opt->repair,
                "Split non-manifold vertices and drop faces with a repeated index (reported on stderr)");
  cmd->add_flag("--overwrite-input", opt->overwrite_input, "Allow OUT to be the input file");
  cmd->footer(
      "The output is written atomically (temporary file, then rename): on failure nothing is left.\n"
      "Exit codes: 0 ok, 1 unreadable or malformed input, 2 bad command line, 3 output not written.");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace freeform::cli
