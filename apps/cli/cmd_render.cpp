// `freeform render MESH [--edit EDIT.json] -o OUT.png [--size WxH] [--view PRESET]
// [--up z|y] [--camera SPEC] [--show original|deformed] [--wireframe] [--background white|light]
// [--band auto|on|off] [--timings]`: headless rendering (EGL, no display) with the renderer the editor uses
// (src/viewer/). With --edit the regions are coloured (support blue, handles green, fixed
// gray; docs/render.md) on the deformed (default) or the original shape.
#include "commands.h"

#include "freeform/bcm/boundary_band.h"
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/repair.h"
#include "freeform/mesh/mesh.h"
#include "viewer/camera.h"
#include "viewer/egl_context.h"
#include "viewer/gl_util.h"
#include "viewer/legend.h"
#include "viewer/offscreen.h"
#include "viewer/region_colors.h"
#include "viewer/render_scene.h"
#include "viewer/renderer.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace freeform::cli {
namespace {

namespace vw = freeform::viewer;
using Clock = std::chrono::steady_clock;

constexpr int kDrawRepeats = 5;  // --timings: the draw time is the median of these

struct RenderOptions {
  std::string mesh, edit, out, size = "640x480", view = "front", camera, show = "deformed", background = "white", up = "z",
      band = "auto";
  bool wireframe = false, timings = false;
  int samples = 4;
};

double ms_since(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

std::pair<int, int> parse_size(const std::string& s) {
  const std::size_t x = s.find('x');
  int w = 0, h = 0;
  const auto ok = [](const char* b, const char* e, int& v) {
    const auto [p, ec] = std::from_chars(b, e, v);
    return ec == std::errc() && p == e && v >= 1 && v <= 8192;
  };
  if (x == std::string::npos || !ok(s.data(), s.data() + x, w) || !ok(s.data() + x + 1, s.data() + s.size(), h))
    throw CLI::ValidationError("--size", "expected WIDTHxHEIGHT with 1..8192 pixels each, e.g. 640x480, got \"" + s + "\"");
  return {w, h};
}

vw::BoundingBox merge(const vw::BoundingBox& a, const vw::BoundingBox& b) {
  return {a.min.cwiseMin(b.min), a.max.cwiseMax(b.max)};
}

// The edit's regions coloured on the scene (and its smoothness band), the scene deformed if
// asked, the frame grown to hold both shapes; returns the order of the smoothness legend to
// draw (0: none).
int show_edit(const RenderOptions& opt, const Mesh& mesh, vw::RenderScene& scene, vw::BoundingBox& frame) {
  int legend_order = 0;
  const Edit edit = read_edit_file(opt.edit, mesh);
  const Regions regions = edit_regions(mesh, edit);
  std::vector<vw::Rgb> colors = vw::region_colors(regions);
  const bool band = opt.band == "on" || (opt.band == "auto" && !edit.settings.smoothness.segments.empty());
  if (band && edit.settings.order > 1) {
    vw::color_smoothness_band(colors, smoothness_band(mesh, regions, edit.settings.order),
                              smoothness_per_vertex(regions, edit.settings));
    legend_order = edit.settings.order;
  }
  vw::set_colors(scene, colors);
  const Mesh deformed = deform(mesh, edit);  // throws on a non-finite result
  vw::RenderScene moved = scene;
  vw::update_geometry(moved, deformed.positions());
  frame = merge(frame, moved.bounds);
  if (opt.show == "deformed") scene = std::move(moved);
  return legend_order;
}

void run(const RenderOptions& opt) {
  // Command-line checks first (exit code 2), then inputs (1), then rendering and output (3).
  const auto [width, height] = parse_size(opt.size);
  if (std::filesystem::path(opt.out).extension() != ".png" && !is_special_file(opt.out))
    throw CLI::ValidationError("-o", "the output must be a .png file, got \"" + opt.out + "\"");
  const std::optional<vw::ViewPreset> preset = vw::parse_view_preset(opt.view);
  if (!preset) throw CLI::ValidationError("--view", "unknown view \"" + opt.view + "\"");
  if (opt.show == "original" && opt.edit.empty())
    throw CLI::ValidationError("--show", "--show original needs --edit (without an edit the mesh is shown as is)");

  for (const std::string& input : {opt.mesh, opt.edit})
    if (!input.empty() && same_file(opt.out, input))
      throw InvalidInput("output " + opt.out + " is the input " + input + "; choose another output");
  ReadResult read = read_mesh(opt.mesh);
  for (const auto& w : read.warnings) fmt::print(stderr, "warning: {}\n", w);
  const Mesh mesh = manifold_mesh(read.soup, opt.mesh);
  vw::RenderScene scene = vw::make_scene(mesh, vw::kPlainColor, /*recentre=*/true);
  vw::BoundingBox frame = scene.bounds;  // fitted to original and deformed: both renders align
  const int legend_order = opt.edit.empty() ? 0 : show_edit(opt, mesh, scene, frame);

  const double aspect = static_cast<double>(width) / height;
  vw::Camera camera = vw::fit_view(frame, *preset, aspect, 1.08, opt.up == "y" ? vw::UpAxis::Y : vw::UpAxis::Z);
  try {
    if (!opt.camera.empty()) {  // the spec is in mesh coordinates, the scene is recentred
      vw::Camera base = camera;
      base.eye = scene.to_mesh(camera.eye);
      base.target = scene.to_mesh(camera.target);
      camera = vw::parse_camera_spec(opt.camera, base);
      camera.eye = scene.to_scene(camera.eye);
      camera.target = scene.to_scene(camera.target);
    }
  } catch (const InvalidInput& e) {
    throw CLI::ValidationError("--camera", e.what());
  }
  camera.fit_clip_planes(frame);

  vw::DrawOptions draw;
  draw.wireframe = opt.wireframe;
  if (opt.background == "light") draw.background = {0.93f, 0.94f, 0.96f};

  std::vector<std::uint8_t> png;
  try {
    auto t0 = Clock::now();
    const vw::EglContext context;
    const double context_ms = ms_since(t0);
    const vw::OffscreenTarget target(width, height, opt.samples);
    vw::Renderer renderer;
    t0 = Clock::now();
    renderer.upload(scene);
    glFinish();
    const double upload_ms = ms_since(t0);
    target.bind();
    std::vector<double> draws;
    for (int i = 0; i < (opt.timings ? kDrawRepeats : 1); ++i) {
      t0 = Clock::now();
      renderer.draw(camera, width, height, draw);
      glFinish();
      draws.push_back(ms_since(t0));
    }
    const double first_draw_ms = draws.front();
    t0 = Clock::now();
    std::vector<std::uint8_t> rgba = target.read_rgba();
    vw::draw_smoothness_legend(rgba, width, height, legend_order);
    const double readback_ms = ms_since(t0);
    t0 = Clock::now();
    png = vw::encode_png(rgba, width, height);
    const double encode_ms = ms_since(t0);
    if (opt.timings) {
      std::sort(draws.begin(), draws.end());
      fmt::print("renderer: {}\n", context.description());
      fmt::print("timings: {} vertices, {} triangles, {}x{} ({} samples): context {:.1f} ms, upload {:.1f} ms, "
                 "draw {:.1f} ms (first {:.1f}, median of {}), readback {:.1f} ms, png {:.1f} ms\n",
                 scene.n_vertices(), scene.n_triangles(), width, height, target.samples(), context_ms, upload_ms,
                 draws[draws.size() / 2], first_draw_ms, draws.size(), readback_ms, encode_ms);
    }
  } catch (const vw::RenderError& e) {
    throw OutputError(std::string("cannot render: ") + e.what());
  }
  try {
    write_file_atomic(opt.out, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
  } catch (const Error& e) {
    throw OutputError(e.what());
  }
  fmt::print("wrote {} ({}x{}, {} triangles{})\n", opt.out, width, height, scene.n_triangles(),
             opt.edit.empty() ? "" : ", " + opt.show);
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto opt = std::make_shared<RenderOptions>();
  CLI::App* cmd = app.add_subcommand("render", "Render a mesh (optionally an edit's regions and result) to a PNG, headless");
  cmd->add_option("MESH", opt->mesh, "Input mesh (OBJ, OFF, PLY, STL, glTF; must be manifold)")->required();
  cmd->add_option("--edit", opt->edit, "Edit file (docs/edit-format.md): colour its regions and apply it");
  cmd->add_option("-o,--output", opt->out, "Output PNG")->required();
  cmd->add_option("--size", opt->size, "Image size WIDTHxHEIGHT")->capture_default_str();
  cmd->add_option("--view", opt->view, "View preset: front, back, left, right, top, bottom, iso")
      ->check(CLI::IsMember({"front", "back", "left", "right", "top", "bottom", "iso"}))
      ->capture_default_str();
  cmd->add_option("--up", opt->up, "World up axis of the view presets: z, or y (e.g. the armadillo)")
      ->check(CLI::IsMember({"z", "y"}))
      ->capture_default_str();
  cmd->add_option("--camera", opt->camera,
                  "Camera override \"eye=x,y,z;target=x,y,z;up=x,y,z;fov=deg\" (any subset; the rest from --view)");
  cmd->add_option("--show", opt->show, "With --edit: draw the deformed or the original shape")
      ->check(CLI::IsMember({"original", "deformed"}))
      ->capture_default_str();
  cmd->add_option("--band", opt->band,
                  "With --edit: colour the boundary-smoothness band by c, with a legend (auto: if the edit has segments)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd->add_flag("--wireframe", opt->wireframe, "Overlay the triangle edges");
  cmd->add_option("--background", opt->background, "white or light (light gray)")
      ->check(CLI::IsMember({"white", "light"}))
      ->capture_default_str();
  cmd->add_option("--samples", opt->samples, "Multisampling samples per pixel (0: off)")
      ->check(CLI::Range(0, 16))
      ->capture_default_str();
  cmd->add_flag("--timings", opt->timings, "Print context, upload, draw, readback and PNG encoding times");
  cmd->footer(
      "Headless: EGL (Mesa surfaceless or an EGL device), no display needed. The view is fitted to the bounding box\n"
      "of the mesh (with --edit: of the original and the deformed shape, so both renders align).\n"
      "Colours with --edit: support blue, movable handles green, fixed gray, immovable handles dark gray; with --band the\n"
      "fixed and handle vertices where boundary smoothness acts go red (C0) - amber (C1) - violet (C2).\n"
      "Exit codes: 0 ok, 1 bad input (mesh, edit), 2 bad command line, 3 no OpenGL/EGL or output not written.");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace freeform::cli
