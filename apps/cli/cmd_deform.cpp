// `freeform deform IN (--edit EDIT.json | --sel F.sel --def F.def [--order k]) -o OUT
// [--deformation linear|nonlinear] [--report REPORT.json]`: applies one BCM edit (docs/edit-format.md) and writes the deformed
// mesh (same vertex order and faces) and optionally a JSON report with counts and timings.
#include "commands.h"

#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_report.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/io/file_util.h"
#include "freeform/io/mesh_io.h"
#include "freeform/io/repair.h"
#include "freeform/mesh/mesh.h"

#include <fmt/core.h>
#include <sys/resource.h>

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace freeform::cli {
namespace {

// The models' names as the library spells them (edit files, reports).
std::vector<std::string> deformation_names() {
  std::vector<std::string> names;
  for (Deformation d : kDeformations) names.emplace_back(deformation_name(d));
  return names;
}

constexpr int kEvaluateRepeats = 51;  // the report's evaluate time is the median of these

struct DeformOptions {
  std::string in, out, edit, sel, def, report, deformation;
  int order = 2;
  bool overwrite_input = false;
};

// Median of one timing over the repeated frames (the report's evaluate and reconstruct times:
// not one cold call).
double median(std::vector<EditTimings> frames, double EditTimings::*field) {
  const auto mid = frames.begin() + static_cast<std::ptrdiff_t>(frames.size() / 2);
  std::nth_element(frames.begin(), mid, frames.end(), [field](const EditTimings& a, const EditTimings& b) { return a.*field < b.*field; });
  return (*mid).*field;
}

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// What was written and how the models went (stdout); the warnings go to stderr (edit_warnings).
void print_summary(const DeformOptions& opt, const ReadResult& read, const EditSolver& solver, double evaluate_ms,
                   double reconstruct_ms) {
  const Regions& regions = solver.regions();
  const BcmStats& st = solver.stats().bcm;
  const std::optional<MultiresStats>& ms = solver.stats().multires;
  fmt::print(
      "wrote {} ({} vertices, {} faces): order {}, {} free, {} fixed, {} handles; solver {}, evaluate {:.3f} ms\n",
      opt.out, read.soup.positions.size(), read.soup.faces.size(), solver.settings().order, regions.n_free(),
      regions.n_fixed(), regions.handles().size(), st.solver, evaluate_ms);
  if (const NonlinearState* ns = solver.nonlinear_state())
    fmt::print("nonlinear: {} iterations, residual {:.2g}, {:.1f} ms\n", ns->iterations, ns->step, ns->ms);
  if (st.anisotropic)
    fmt::print("anisotropic bending: principal extents {:.4g} x {:.4g} equalized (parametrization {:.1f} ms)\n",
               st.principal_extents[0], st.principal_extents[1], st.parametrization_ms);
  if (ms && ms->detail_by_model) {
    fmt::print("multiresolution: {}\n", ms->operator_fallback);
  } else if (ms) {
    if (ms->vertex_frames > 0)
      fmt::print("multiresolution: decomposition {:.1f} ms, reconstruct {:.3f} ms; {} vertices in vertex frames\n",
                 ms->decomposition_ms, reconstruct_ms, ms->vertex_frames);
    else
      fmt::print("multiresolution: decomposition {:.1f} ms, reconstruct {:.3f} ms; {} normal-encoded, {} fallback vertices\n",
                 ms->decomposition_ms, reconstruct_ms, ms->normal_encoded, ms->fallback);
    if (!ms->operator_fallback.empty()) fmt::print("multiresolution: {}\n", ms->operator_fallback);
    if (!solver.detail_carried().empty()) fmt::print("multiresolution: {}\n", solver.detail_carried());
  }
}

void run(const DeformOptions& opt) {
  if (same_file(opt.in, opt.out) && !opt.overwrite_input)
    throw InvalidInput("output " + opt.out + " is the input file; pass --overwrite-input to replace it");
  // Never overwrite what the edit was read from, nor write the report over a mesh.
  struct Named {
    const std::string& path;
    const char* what;
    bool edit_input;  // read by the edit: never an output
  };
  for (const auto& [path, what, edit_input] : {Named{opt.edit, "edit file", true}, Named{opt.sel, ".sel file", true},
                                               Named{opt.def, ".def file", true}, Named{opt.in, "input mesh", false},
                                               Named{opt.out, "output mesh", false}}) {
    if (path.empty()) continue;
    if (edit_input && same_file(opt.out, path))
      throw InvalidInput("output " + opt.out + " is the " + what + " " + path + "; choose another output");
    if (!opt.report.empty() && same_file(opt.report, path))
      throw InvalidInput("the report " + opt.report + " would overwrite the " + what + " " + path);
  }
  WriteOptions wo;
  wo.format = format_from_path(opt.out);  // refuse an unknown extension before any work

  ReadResult read = read_mesh(opt.in);
  for (const auto& w : read.warnings) fmt::print(stderr, "warning: {}\n", w);
  const Mesh mesh = manifold_mesh(read.soup, opt.in);

  Edit edit = opt.edit.empty() ? edit_from_sel_def(opt.sel, opt.def, opt.order, mesh) : read_edit_file(opt.edit, mesh);
  if (!opt.deformation.empty()) edit.deformation = *deformation_from_name(opt.deformation);  // checked by CLI11
  const EditSolver solver(mesh, edit);
  const std::vector<Eigen::Affine3d> transforms = solver.transforms(edit);
  VertexData<Vec3> positions = mesh.positions();
  // The report's frame times: medians of warm calls (evaluate writes the same result each time).
  std::vector<EditTimings> frames;
  // A nonlinear frame is a whole solve: once is enough (and its report gives its iterations).
  const int repeats = edit.deformation == Deformation::Linear ? kEvaluateRepeats : 1;
  frames.reserve(repeats);
  for (int i = 0; i < repeats; ++i) {
    solver.evaluate(transforms, positions);
    frames.push_back(solver.last_timings());
  }
  const double evaluate_ms = median(frames, &EditTimings::evaluate_ms);
  const double reconstruct_ms = median(frames, &EditTimings::reconstruction_ms);
  const EditProblems problems = solver.problems(positions);
  require_finite(problems, transforms);
  // The output is the input file with the solve's positions (and everything else it held).
  const std::span<const Vec3> out_positions(positions.raw().data(), read.soup.positions.size());

  Json report = {
      {"input", opt.in},
      {"output", opt.out},
      {"edit", opt.edit.empty() ? Json({{"sel", opt.sel}, {"def", opt.def}}) : Json(opt.edit)},
      {"vertices", mesh.n_vertices()},
      {"faces", mesh.n_faces()},
  };
  report.update(edit_report(solver, {evaluate_ms, reconstruct_ms}, problems));
  report["evaluate_repeats"] = repeats;
  if (!report["multiresolution"].is_null()) report["multiresolution"]["reconstruct_repeats"] = repeats;
  report["peak_memory_mb"] = peak_memory_mb();

  // Both files are written to temporaries first and renamed only when both succeeded: a
  // failure leaves whatever was there before (an earlier output included) untouched.
  try {
    MeshBytes bytes = mesh_bytes(opt.out, read, out_positions, wo);
    for (const std::string& d : bytes.dropped) fmt::print(stderr, "note: {} cannot hold the input's {}\n", opt.out, d);
    std::vector<std::unique_ptr<PreparedFile>> files = prepare_mesh_files(opt.out, bytes);
    if (!opt.report.empty()) files.push_back(std::make_unique<PreparedFile>(opt.report, report.dump(2) + "\n"));
    for (const auto& f : files) f->commit();
  } catch (const Error& e) {
    throw OutputError(e.what());
  }
  print_summary(opt, read, solver, evaluate_ms, reconstruct_ms);
  for (const std::string& w : edit_warnings(solver, problems, solver.nonlinear_state()))
    fmt::print(stderr, "warning: {}\n", w);
  if (!opt.report.empty()) fmt::print("wrote {}\n", opt.report);
}

}  // namespace

void add_deform_command(CLI::App& app) {
  auto opt = std::make_shared<DeformOptions>();
  CLI::App* cmd = app.add_subcommand("deform", "Apply a BCM edit (support, handles, transforms) to a mesh");
  cmd->add_option("IN", opt->in, "Input mesh (OBJ, OFF, PLY, STL, glTF; must be manifold)")->required();
  CLI::Option* edit = cmd->add_option("--edit", opt->edit, "Edit file (JSON, docs/edit-format.md)");
  CLI::Option* sel = cmd->add_option("--sel", opt->sel, "Botsch-Sorkine .sel file: 0 fixed, 1 free, 2 handle per vertex");
  CLI::Option* def = cmd->add_option("--def", opt->def, "Botsch-Sorkine .def file: the handle's 4x4 matrix");
  CLI::Option* order = cmd->add_option("--order", opt->order, "With --sel/--def: energy order k (1, 2, 3)")
                           ->check(CLI::Range(1, 3));
  cmd->add_option("-o,--output", opt->out, "Output mesh; format from the extension")->required();
  cmd->add_option("--deformation", opt->deformation,
                  "linear (the paper's BCM) or nonlinear (rotation-aware, large rotations); default: the edit's")
      ->check(CLI::IsMember(deformation_names()));
  cmd->add_option("--report", opt->report, "Write a JSON report (counts, solver, timings, memory)");
  cmd->add_flag("--overwrite-input", opt->overwrite_input, "Allow the output to be the input file");
  edit->excludes(sel)->excludes(def)->excludes(order);
  sel->needs(def);
  def->needs(sel);
  cmd->footer(
      "Give either --edit or --sel with --def. Outputs are written atomically: on failure nothing is left.\n"
      "Exit codes: 0 ok, 1 bad input (mesh, edit, regions), 2 bad command line, 3 output not written.");
  cmd->callback([opt, cmd] {
    if (opt->edit.empty() && opt->sel.empty())
      throw CLI::RequiredError(cmd->get_name() + ": give --edit EDIT.json, or --sel F.sel with --def F.def");
    run(*opt);
  });
}

}  // namespace freeform::cli
