// freeform-editor [MESH] [--size WxH] [--session FILE] [--frame-log FILE]
// The interactive editor (docs/editor.md). Exit codes: 0 normal quit, 1 no window / OpenGL,
// 2 bad command line.
#include "app.h"

#include "freeform/common/huge_pages.h"

#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <charconv>
#include <exception>
#include <string>

namespace {

std::pair<int, int> parse_size(const std::string& s) {
  const std::size_t x = s.find('x');
  int w = 0, h = 0;
  const auto ok = [](const char* b, const char* e, int& v) {
    const auto [p, ec] = std::from_chars(b, e, v);
    return ec == std::errc() && p == e && v >= 200 && v <= 16384;
  };
  if (x == std::string::npos || !ok(s.data(), s.data() + x, w) || !ok(s.data() + x + 1, s.data() + s.size(), h))
    throw CLI::ValidationError("--size", "expected WIDTHxHEIGHT with 200..16384 pixels each, e.g. 1280x800, got \"" + s + "\"");
  return {w, h};
}

}  // namespace

int main(int argc, char** argv) {
  freeform::restart_with_huge_page_malloc(argv);
  CLI::App cli{"Freeform editor: paint regions, drag handles, export edits (docs/editor.md)", "freeform-editor"};
  freeform::editor::AppOptions options;
  std::string size = "1280x800";
  cli.add_option("mesh", options.mesh, "Mesh to open (OBJ, OFF, PLY, STL, glTF)");
  cli.add_option("--size", size, "Window size WIDTHxHEIGHT")->capture_default_str();
  cli.add_option("--session", options.session, "Session file to load at start (regions, parameters, edit, history)");
  cli.add_option("--frame-log", options.frame_log,
                 "Write one JSON line per frame with the timings to FILE (atomically, at exit)");
  try {
    cli.parse(argc, argv);
    std::tie(options.width, options.height) = parse_size(size);
  } catch (const CLI::ParseError& e) {
    return cli.exit(e);
  }
  try {
    freeform::editor::App app(options);
    return app.run();
  } catch (const std::exception& e) {
    fmt::print(stderr, "freeform-editor: {}\n", e.what());
    return 1;
  }
}
