// The editor's interactive frame, headless (docs/benchmarks.md, "Editor frame"): on a mesh of
// about 250k triangles with a 35k-vertex support, one frame of a handle drag is
//   evaluate (BCM basis product) + detail reconstruction (Document::update_display)
//   + positions, normals and bounds of the moving part (viewer::GeometryPatch) + GPU upload of
//   its vertex range (Renderer::update_geometry, glFinish); the whole-mesh path it replaced is
//   timed too (whole_mesh_*) and checked to give the same floats every frame
// and, separately, the draw (Renderer::draw + glFinish; on Mesa llvmpipe this is software
// rasterization on the CPU). The same calls the editor makes per frame, on an EGL surfaceless
// context. Prints JSON with medians over the frames, and the platform's own tail for
// comparison (reference_compute: a computation as long as the evaluate, timed alongside it).
//
// Meshes: armadillo.off (52k triangles) and bunny00.off (75k) with one midpoint subdivision:
// 208k and 302k triangles. Support: 35k free vertices + a 700-vertex handle, breadth-first
// from a seed vertex; k = 3, multiresolution on (the editor's default).
#include "bench_meshes.h"
#include "editor/document.h"
#include "freeform/common/huge_pages.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/traversal.h"
#include "viewer/egl_context.h"
#include "viewer/geometry_patch.h"
#include "viewer/offscreen.h"
#include "viewer/region_colors.h"
#include "viewer/render_scene.h"
#include "viewer/renderer.h"

#include <GL/gl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace {

using namespace freeform;
using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// Nearest-rank percentile (q in (0, 1]).
double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::min(v.size(), std::max<std::size_t>(rank, 1)) - 1];
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The platform's own tail: a chain of dependent multiply-adds (no memory, no threads, no
// system calls) timed like the evaluate. Its p99 over its median is what interrupts, the
// scheduler and the hypervisor add to any computation of that length on this machine.
double reference_compute_ms(long iterations) {
  const auto t = Clock::now();
  volatile double seed = 1.0;
  double x = seed;
  for (long i = 0; i < iterations; ++i) x = x * 0.9999999 + 1e-9;
  seed = x;
  return ms_since(t);
}

nlohmann::json run(const std::string& name, int frames, int width, int height, int samples, bool nonlinear, int order) {
  const auto path = bench::mesh_dir() / name;
  Mesh mesh = Mesh::from_soup(bench::subdivide_midpoint(read_mesh(path.string()).soup));
  const int n_free = 35000, n_handle = 700;
  const Vertex seed[] = {Vertex(1000)};
  const std::vector<Vertex> bfs = k_ring(mesh, seed, 100000);
  std::vector<Vertex> handle(bfs.begin(), bfs.begin() + n_handle);
  std::vector<Vertex> support(bfs.begin(), bfs.begin() + n_handle + n_free);

  editor::Document doc;
  doc.open_mesh(std::move(mesh), path.string());
  doc.set_region(editor::PaintMode::Support, support, false);
  doc.set_region(editor::PaintMode::Handle, handle, false);
  if (nonlinear || order != 3) {
    editor::EditParameters p = doc.parameters();
    if (nonlinear) p.deformation = Deformation::Nonlinear;
    p.settings.order = order;
    doc.set_parameters(p);
  }
  const auto t_pre = Clock::now();
  doc.wait_for_precompute();
  const double precompute_ms = ms_since(t_pre);
  if (!doc.solver_current()) throw std::runtime_error("precompute failed: " + doc.last_error());
  const int id = doc.active_handle();

  viewer::EglContext context;
  viewer::OffscreenTarget target(width, height, samples);
  target.bind();
  viewer::Renderer renderer;
  viewer::RenderScene scene = viewer::make_scene(doc.rest_mesh(), viewer::kPlainColor);
  renderer.upload(scene);
  const viewer::Camera camera = viewer::fit_view(scene.bounds, viewer::ViewPreset::Iso, double(width) / height);
  const double diag = 2.0 * scene.bounds.radius();

  int predicted = 0;  // nonlinear frames that showed a prediction (the worker behind the handle)
  std::vector<double> iterations, evaluate, reconstruction, update, normals, upload, frame, draw, full_normals, full_upload, full_frame;
  const Manipulator start = doc.state().find_handle(id)->manipulator;
  viewer::RenderScene full = scene;  // the whole-mesh path, for the before/after comparison
  doc.update_display();
  viewer::update_geometry(scene, doc.display_positions());
  const viewer::GeometryPatch patch(scene, doc.display_touched());
  // The reference computation lasts as long as the evaluate: medians of both over 21 warm-up
  // frames, timed next to each other (this VM's speed drifts between runs).
  constexpr long kProbe = 20000;
  std::vector<double> warm_up, probe;
  for (int f = 0; f < 21; ++f) {
    Manipulator m = start;
    m.translation += Vec3(0.0, 1e-4 * diag * (f % 2 + 1), 0.0);
    doc.preview_manipulator(id, m);
    warm_up.push_back(doc.update_display().evaluate_ms);
    probe.push_back(reference_compute_ms(kProbe));
  }
  doc.preview_manipulator(id, start);
  doc.update_display();
  const long reference_iterations = std::max(1L, std::lround(kProbe * median(warm_up) / median(probe)));
  std::vector<double> reference;
  Clock::time_point frame_start = Clock::now();
  for (int f = 0; f < frames; ++f) {
    Manipulator m = start;
    m.translation += Vec3(0.0, 0.05 * diag * std::sin(0.1 * (f + 1)), 0.02 * diag);
    // The nonlinear model is for rotations: the handle also turns, up to 90 degrees.
    if (nonlinear) m.rotation = Eigen::AngleAxisd(1.5708 * (f + 1) / frames, Vec3::UnitX()) * m.rotation;
    // The nonlinear model's worker runs between frames: pace them like a 60 Hz display.
    if (nonlinear && f > 0) std::this_thread::sleep_until(frame_start + std::chrono::microseconds(16667));
    frame_start = Clock::now();
    // First after the draw or second: a thread that blocked in glFinish may wake on a busy core
    // and wait for a slice; alternating gives the reference the evaluate's exposure to that.
    if (f % 2 == 0) reference.push_back(reference_compute_ms(reference_iterations));
    doc.preview_manipulator(id, m);
    auto t = Clock::now();
    const editor::FrameTimings ft = doc.update_display();
    const double update_ms = ms_since(t);
    if (f % 2 == 1) reference.push_back(reference_compute_ms(reference_iterations));
    // Before: every vertex converted, every normal and the bounds recomputed, whole buffers.
    t = Clock::now();
    viewer::update_geometry(full, doc.display_positions());
    full_normals.push_back(ms_since(t));
    t = Clock::now();
    renderer.update_geometry(full);
    glFinish();
    full_upload.push_back(ms_since(t));
    // Now (the editor's path): the patch of the moving part and one sub-buffer range.
    t = Clock::now();
    patch.apply(scene, doc.display_positions());
    const double normals_ms = ms_since(t);
    t = Clock::now();
    renderer.update_geometry(scene, patch.ranges());
    glFinish();
    const double upload_ms = ms_since(t);
    if (scene.positions != full.positions || scene.normals != full.normals)
      throw std::runtime_error("the patched scene differs from the full recomputation");
    t = Clock::now();
    renderer.draw(camera, width, height);
    glFinish();
    draw.push_back(ms_since(t));
    evaluate.push_back(ft.evaluate_ms);
    iterations.push_back(ft.iterations);
    if (ft.predicted) ++predicted;
    reconstruction.push_back(ft.reconstruction_ms);
    update.push_back(update_ms);
    normals.push_back(normals_ms);
    upload.push_back(upload_ms);
    frame.push_back(update_ms + normals_ms + upload_ms);
    full_frame.push_back(update_ms + full_normals.back() + full_upload.back());
  }
  // The nonlinear model when the handle rests: the worker iterates while the editor's loop
  // wakes at 30 Hz to show its newest iterate (App::run), until it settled.
  nlohmann::json settle;
  if (nonlinear) {
    const auto t = Clock::now();
    std::vector<double> rest_frames, steps;
    while (doc.refining() && ms_since(t) < 600000.0) {
      const auto tf = Clock::now();
      const editor::FrameTimings ft = doc.update_display();
      if (ft.evaluated) {
        rest_frames.push_back(ms_since(tf));
        steps.push_back(ft.residual);
      }
      std::this_thread::sleep_until(tf + std::chrono::microseconds(33333));
    }
    settle = {{"shown_iterates", rest_frames.size()},
              {"iterations", doc.last_timings().iterations},
              {"converged", doc.last_timings().converged},
              {"last_step", doc.last_timings().residual},
              {"steps", steps},
              {"median_frame_ms", rest_frames.empty() ? 0.0 : median(rest_frames)},
              {"max_frame_ms", rest_frames.empty() ? 0.0 : *std::max_element(rest_frames.begin(), rest_frames.end())},
              {"total_ms", ms_since(t)}};
  }
  return {{"mesh", name + " (1 midpoint subdivision)"},
          {"nonlinear_settle", settle},
          {"nonlinear_predicted_frames", predicted},
          {"vertices", doc.rest_mesh().n_vertices()},
          {"triangles", doc.rest_mesh().n_faces()},
          {"support", doc.state().n_support()},
          {"free", doc.state().n_free()},
          {"handle", n_handle},
          {"order", doc.parameters().settings.order},
          {"multiresolution", doc.parameters().multiresolution},
          {"deformation", nonlinear ? "nonlinear" : "linear"},
          {"precompute_ms", precompute_ms},
          {"frames", frames},
          {"viewport", std::to_string(width) + "x" + std::to_string(height) + " " + std::to_string(samples) + "xMSAA"},
          {"gl", context.description()},
          {"median_ms",
           {{"evaluate", median(evaluate)},
            {"nonlinear_iterations", median(iterations)},
            {"reconstruction", median(reconstruction)},
            {"update_display", median(update)},
            {"normals", median(normals)},
            {"upload", median(upload)},
            {"interactive_frame", median(frame)},
            {"draw", median(draw)},
            {"whole_mesh_normals", median(full_normals)},
            {"whole_mesh_upload", median(full_upload)},
            {"whole_mesh_interactive_frame", median(full_frame)}}},
          {"patch_upload_vertices", patch.range_vertices()},
          {"patch_ranges", patch.ranges().size()},
          {"p99_ms", {{"evaluate", percentile(evaluate, 0.99)}, {"update_display", percentile(update, 0.99)},
                      {"interactive_frame", percentile(frame, 0.99)}}},
          {"max_ms", {{"interactive_frame", *std::max_element(frame.begin(), frame.end())}}},
          {"reference_compute", {{"median_ms", median(reference)}, {"p99_ms", percentile(reference, 0.99)}}}};
}

}  // namespace

int main(int argc, char** argv) {
  // bench_editor_frame [frames] [nonlinear] [busy] [k1|k2|k3]: `nonlinear` runs the nonlinear
  // model on a rotating drag; `busy` keeps one core busy meanwhile with a spinning child process
  // (a user's machine is never idle; forked before any thread exists); k1-k3 the order (3, the
  // editor's default, unless given). Restarts as the editor does.
  freeform::restart_with_huge_page_malloc(argv);
  const int frames = argc > 1 ? std::max(5, std::atoi(argv[1])) : 60;
  bool nonlinear = false, busy = false;
  int order = 3;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "nonlinear") nonlinear = true;
    else if (a == "busy") busy = true;
    else if (a == "k1" || a == "k2" || a == "k3")
      order = a[1] - '0';
    else {
      std::cerr << "bench_editor_frame: unknown argument '" << a << "' (expected nonlinear, busy, k1, k2 or k3)\n";
      return 2;
    }
  }
  pid_t spinner = -1;
  if (busy) {
    spinner = fork();
    if (spinner == 0) {
      std::atomic<unsigned long> spin{0};
      for (;;) spin.fetch_add(1, std::memory_order_relaxed);
    }
    if (spinner < 0) {
      std::cerr << "bench_editor_frame: cannot start the busy process\n";
      return 1;
    }
  }
  const auto stop_spinner = [&] {
    if (spinner > 0) {
      kill(spinner, SIGKILL);
      waitpid(spinner, nullptr, 0);
    }
  };
  try {
    nlohmann::json out = nlohmann::json::array();
    for (const char* name : {"armadillo.off", "bunny00.off"}) {
      out.push_back(run(name, frames, 1280, 800, 4, nonlinear, order));
      out.back()["one_core_busy"] = busy;
    }
    stop_spinner();
    std::cout << out.dump(2) << "\n";
  } catch (const std::exception& e) {
    stop_spinner();
    std::cerr << "bench_editor_frame: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
