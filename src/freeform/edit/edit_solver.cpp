#include "freeform/edit/edit_solver.h"

#include "freeform/common/error.h"
#include "freeform/common/json_messages.h"
#include "freeform/mesh/seams.h"
#include "freeform/multires/operator_shape.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

namespace freeform {
namespace {

std::vector<Vertex> touched_vertices(const Regions& regions) {
  std::vector<Vertex> out = regions.free_vertices();
  for (const HandleRegion& h : regions.handles())
    if (h.movable) out.insert(out.end(), h.vertices.begin(), h.vertices.end());
  std::sort(out.begin(), out.end());
  return out;
}

// A closed component whose constraints are all movable handles: the linear fill from the
// handles alone replaces the whole surface and collapses onto them (a sphere shrinks to a
// blob, multiresolution detail then explodes), so it is refused with the way out.
void refuse_unanchored_closed_components(const Mesh& mesh, const Regions& regions) {
  VertexData<char> seen(static_cast<std::size_t>(mesh.n_vertices()), 0);
  std::vector<Vertex> stack;
  for (Vertex start : regions.free_vertices()) {
    if (seen[start]) continue;
    bool closed = true, anchored = false;
    int size = 0;
    seen[start] = 1;
    stack.assign(1, start);
    while (!stack.empty()) {
      const Vertex v = stack.back();
      stack.pop_back();
      ++size;
      const Role r = regions.role(v);
      if (r == Role::Fixed || (r == Role::Handle && regions.movable_index(regions.handle_of(v)) < 0)) anchored = true;
      for (Halfedge h : mesh.outgoing(v)) {
        if (mesh.is_boundary(h) || mesh.is_boundary(mesh.opposite(h))) closed = false;
        const Vertex w = mesh.to_vertex(h);
        if (!seen[w]) {
          seen[w] = 1;
          stack.push_back(w);
        }
      }
    }
    if (closed && !anchored)
      throw InvalidInput("the support covers all of a closed component (" + std::to_string(size) +
                         " vertices, free vertex " + std::to_string(start.idx()) +
                         ") that only movable handles hold: the linear model replaces it by the fill between the "
                         "handles, which collapses onto them. Leave part of it out of the support (fixed), make a "
                         "handle immovable, use \"deformation\": \"nonlinear\", or set \"allow_unanchored\": true");
  }
}

// Free rows in `bcm`'s order and the movable handles moved by `transforms`, into `positions`.
void write_rows(const BcmSolver& bcm, std::span<const Eigen::Affine3d> transforms,
                Eigen::Ref<const BcmSolver::RowMatrixX3d> free_rows, VertexData<Vec3>& positions) {
  const std::vector<Vertex>& free = bcm.free_vertices();
  for (std::size_t i = 0; i < free.size(); ++i)
    positions[free[i]] = free_rows.row(static_cast<Eigen::Index>(i)).transpose();
  bcm.move_handles(transforms, positions);
}

// The same edit at order k - 1, each boundary smoothness capped at C^(k-2).
Edit lower_order(const Edit& edit) {
  Edit lower = edit;
  BcmSettings& s = lower.settings;
  const double cap = s.order - 2;
  s.order -= 1;
  s.smoothness.outer = std::min(resolved_outer(edit.settings), cap);
  s.smoothness.inner = std::min(resolved_inner(edit.settings), cap);
  for (SmoothnessSegment& segment : s.smoothness.segments) segment.value = std::min(segment.value, cap);
  return lower;
}

}  // namespace

// Order 3 raises the cotangents and area ratios of the support's triangles to the third power:
// on a CAD part's needle fans that system can be beyond double precision: its factorization
// fails, or its solve is far from the solution (the refinement against the unassembled
// operator does not converge), while order 2 solves (docs/bcm.md). Such an edit is solved at
// order 2 and says so, rather than refused or returned wrong.
EditSolver::EditSolver(const Mesh& mesh, const Edit& edit, const Progress& progress)
    : regions_(edit_regions(mesh, edit)),
      settings_(edit.settings),
      touched_(touched_vertices(regions_)),
      folds_(mesh, mesh.positions(), touched_) {
  std::string failure;
  try {
    build(mesh, edit, progress);
    if (edit.settings.order == 3 && !(stats_.bcm.forward_error <= kForwardErrorWarning)) {
      failure = fmt::format("the order-3 solve's estimated error is {:.2g} of the bounding-box diagonal",
                            stats_.bcm.forward_error);
      if (const std::string needle = needle_cause(mesh, regions_.free_vertices(), 3); !needle.empty())
        failure += "; " + needle;
    }
  } catch (const SolverError& e) {
    if (edit.settings.order < 3) throw;
    failure = std::string("the order-3 system failed (") + e.what() + ")";
  }
  if (failure.empty()) return;
  const Edit lower = lower_order(edit);
  bcm_.reset();
  multires_.reset();
  model_.reset();
  carried_.reset();
  stats_ = {};
  try {
    build(mesh, lower, progress);
  } catch (const SolverError& again) {
    throw SolverError(failure + "; at order 2 as well: " + again.what());
  }
  settings_ = lower.settings;
  stats_.order_fallback = failure + "; solved at order 2";
}

struct EditSolver::Carried {
  explicit Carried(const Mesh& m) : mesh(m) {}
  Mesh mesh;  // a copy: the solvers are built on the first frame that needs them
  std::unique_ptr<BcmSolver> bcm;
  std::unique_ptr<NonlinearSolver> model;
  std::vector<Vec3> decomposed;  // the touched vertices' decomposed positions (workspace)
  std::string why;             // of the last frame (detail_carried())
};

void EditSolver::build(const Mesh& mesh, const Edit& edit, const Progress& progress) {
  progress.check();
  const PhaseClock whole;
  stats_.deformation = edit.deformation;
  const bool nonlinear = edit.deformation == Deformation::Nonlinear;
  if (nonlinear) nonlinear_options_ = edit.nonlinear;
  if (!nonlinear && !edit.allow_unanchored) refuse_unanchored_closed_components(mesh, regions_);
  for (Vertex v : edit.support)
    if (v.idx() >= 0 && v.idx() < mesh.n_vertices() && !mesh.halfedge(v).is_valid()) ++stats_.isolated_ignored;
  if (const auto seam = open_seam_pairs(mesh, regions_.free_vertices()); !seam.empty()) {
    stats_.open_seam_vertices = static_cast<int>(seam.size());
    stats_.open_seam_example = seam.front();
  }
  // The BCM system's ordering runs on another thread during the operator shape (bcm_analysis.h).
  BcmAnalysis analysis(mesh, regions_, edit.settings);
  // The smooth foot-point shape: the nonlinear model's base operator, and for both models what
  // says whether the detail stands on its base (multires_solver.h, MultiresOptions::Encoding).
  std::optional<OperatorShape> shape;
  if (edit.multiresolution) {
    const PhaseClock clock;
    shape = base_operator_shape(mesh, regions_, edit.settings, progress);
    stats_.phases.push_back({"operator_shape", clock.elapsed()});
  }
  // Detail that overhangs its base (an ear, fingers, a snout) does not ride on the base's
  // normals through a large rotation: re-added along the turned normals it tore (the bunny's
  // ear twisted 90 degrees: 446 folded edges, 0 without the decomposition). Nor does the detail
  // the base invents where its free edge curls away from a curved open boundary (lifted
  // boundary: decomposed, 8-10 of 72 edits on open meshes folded more than without it). The
  // nonlinear model carries such detail itself, as it does without multiresolution: it
  // rotates the detailed mesh's Laplacian coordinates (docs/nonlinear.md).
  bool detail_by_model = nonlinear && shape && (shape->overhanging > 0 || shape->lifted_boundary > 0);
  if (edit.multiresolution && !detail_by_model) {
    MultiresOptions options;
    if (nonlinear) options.model = nonlinear_base_model(edit.nonlinear);
    try {
      multires_ = std::make_unique<MultiresSolver>(mesh, regions_, edit.settings, options, progress, *shape, &analysis);
    } catch (const SolverError& e) {
      // The base system on the foot-point shape can still be numerically singular where the
      // projection nearly degenerates (operator_shape.h). The linear model then bends the base
      // with the detailed mesh's operator; the nonlinear one carries the detail itself.
      if (shape->positions.size() == 0) throw;
      shape->fallback = std::string("the base system on the smooth shape failed (") + e.what() + ")";
      shape->positions = VertexData<Vec3>(0);
      if (nonlinear)
        detail_by_model = true;
      else
        multires_ =
            std::make_unique<MultiresSolver>(mesh, regions_, edit.settings, options, progress, *shape, &analysis);
    }
  }
  if (!multires_) {
    // The plain linear frame scatters rows into the mesh: rows in vertex order (RowOrder).
    bcm_ = std::make_unique<BcmSolver>(mesh, regions_, edit.settings, progress, nullptr, nonlinear,
                                       nonlinear ? RowOrder::BreadthFirst : RowOrder::ByIndex, &analysis);
    if (nonlinear) model_ = std::make_unique<NonlinearSolver>(mesh, regions_, *bcm_, mesh.positions(), edit.nonlinear);
  }
  if (multires_ && nonlinear) carried_ = std::make_unique<Carried>(mesh);
  stats_.bcm = bcm().stats();
  if (multires_) stats_.multires = multires_->stats();
  if (detail_by_model) {
    MultiresStats& ms = stats_.multires.emplace();
    ms.free = regions_.n_free();
    ms.detail_by_model = true;
    std::string why = shape->fallback;
    if (shape->overhanging > 0)
      why = "the detail overhangs its base at " + std::to_string(shape->overhanging) + " triangles";
    else if (shape->lifted_boundary > 0)
      why =
          "the smooth base leaves the mesh's open boundary at " + std::to_string(shape->lifted_boundary) + " vertices";
    ms.operator_fallback = why + "; the nonlinear model carries it on the detailed mesh (no decomposition)";
    ms.operator_shape_ms = ms.decomposition_ms = shape->ms;
  }
  stats_.precompute = whole.elapsed();
  PhaseTime rest = stats_.precompute;
  for (const Phase& p : stats_.phases) rest = rest - p.time;
  for (const Phase& p : stats_.bcm.phases) rest = rest - p.time;
  stats_.phases.insert(stats_.phases.end(), stats_.bcm.phases.begin(), stats_.bcm.phases.end());
  stats_.phases.push_back({"model_setup", rest});
}

EditSolver::~EditSolver() = default;
EditSolver::EditSolver(EditSolver&&) noexcept = default;
EditSolver& EditSolver::operator=(EditSolver&&) noexcept = default;

const BcmSolver& EditSolver::bcm() const { return multires_ ? multires_->bcm() : *bcm_; }

Vec3 EditSolver::handle_centroid(int movable) const { return bcm().handle_centroid(movable); }

std::vector<Eigen::Affine3d> EditSolver::transforms(const Edit& edit) const {
  if (freeform::n_movable(edit) != n_movable())
    throw InvalidInput("the edit has " + std::to_string(freeform::n_movable(edit)) + " movable handles, the solver " +
                       std::to_string(n_movable()) + ": build the solver from this edit");
  std::vector<Eigen::Affine3d> out;
  for (const EditHandle& h : edit.handles) {
    if (!h.movable) continue;
    const int m = static_cast<int>(out.size());
    out.push_back(h.matrix ? *h.matrix : h.manipulator.to_affine(handle_centroid(m)));
  }
  return out;
}

IterativeModel* EditSolver::iterative_model() const { return multires_ ? multires_->model() : model_.get(); }

const NonlinearOptions* EditSolver::nonlinear_options() const {
  return nonlinear_options_ ? &*nonlinear_options_ : nullptr;
}

const NonlinearState* EditSolver::nonlinear_state() const {
  if (!detail_carried().empty()) return &carried_->model->state();
  return iterative_model() ? &iterative_model()->state() : nullptr;
}

const std::string& EditSolver::detail_carried() const {
  static const std::string none;
  return carried_ ? carried_->why : none;
}

void EditSolver::show(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<const BcmSolver::RowMatrixX3d> free_rows,
                      VertexData<Vec3>& positions) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices()))
    throw InvalidInput("evaluate: positions have " + std::to_string(positions.size()) + " entries, the mesh has " +
                       std::to_string(n_vertices()) + " vertices");
  if (multires_) {
    multires_->reconstruct(transforms, free_rows, positions);
    timings_.reconstruction_ms = multires_->last_timings().detail_ms;
    return;
  }
  if (free_rows.rows() != static_cast<Eigen::Index>(bcm_->free_vertices().size()))
    throw InvalidInput("show: " + std::to_string(free_rows.rows()) + " rows for " +
                       std::to_string(bcm_->free_vertices().size()) + " free vertices");
  if (static_cast<int>(transforms.size()) != n_movable())
    throw InvalidInput("show: got " + std::to_string(transforms.size()) + " transforms for " +
                       std::to_string(n_movable()) + " movable handles");
  write_rows(*bcm_, transforms, free_rows, positions);
  timings_.reconstruction_ms = 0.0;
}

void EditSolver::evaluate(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                          const Progress& progress) const {
  if (model_) {
    model_->start(transforms, false, nullptr);
    model_->run(progress);
    timings_.evaluate_ms = model_->state().ms;
    show(transforms, model_->free_positions(), positions);
    return;
  }
  if (multires_) {
    multires_->evaluate(transforms, positions, progress);
    timings_ = {multires_->last_timings().base_ms, multires_->last_timings().detail_ms};
    if (carried_) carry_failed_detail(transforms, positions, progress);
    return;
  }
  const auto start = std::chrono::steady_clock::now();
  bcm_->evaluate(transforms, positions);
  timings_ = {std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count(), 0.0};
}

// The decomposition can fail the nonlinear model where the base bends tighter than the detail
// is tall (a dent next to a crease, a limb turned in place): the detail re-added to the base
// flips or is flattened, and edges fold that the model carrying the detail on the detailed mesh,
// as without multiresolution, leaves flat. Where a frame's detail fails or its edges fold, the
// frame is solved that way too and the result with fewer folded edges is kept (ties: the
// decomposition's, unless its detail failed), so the decomposition stays where it holds the
// detail's shape (the survey plane's bumps) (docs/nonlinear.md, "Detail that overhangs its base").
void EditSolver::carry_failed_detail(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                                     const Progress& progress) const {
  Carried& c = *carried_;
  c.why.clear();
  const MultiresProblems failed = multires_->problems(positions);
  const int decomposed = folds_.count(positions);
  if (failed.ok() && decomposed == 0) return;
  if (!c.model) {
    c.bcm = std::make_unique<BcmSolver>(c.mesh, regions_, settings_, progress, nullptr, true);
    c.model = std::make_unique<NonlinearSolver>(c.mesh, regions_, *c.bcm, c.mesh.positions(), *nonlinear_options_);
  }
  c.model->start(transforms, false, nullptr);
  c.model->run(progress);
  timings_.evaluate_ms += c.model->state().ms;
  c.decomposed.resize(touched_.size());
  for (std::size_t i = 0; i < touched_.size(); ++i) c.decomposed[i] = positions[touched_[i]];
  write_rows(*c.bcm, transforms, c.model->free_positions(), positions);
  const int carried = folds_.count(positions);
  if (carried > decomposed || (carried == decomposed && failed.ok())) {
    for (std::size_t i = 0; i < touched_.size(); ++i) positions[touched_[i]] = c.decomposed[i];
    return;
  }
  timings_.reconstruction_ms = 0.0;
  c.why = fmt::format(
      "the detail re-added to the base folded {} edges (flipped {} detail triangles, flattened {} vertices); "
      "the nonlinear model carried it on the detailed mesh (no decomposition) for this frame",
      decomposed, failed.flipped, failed.overlaps);
}

EditProblems EditSolver::problems(const VertexData<Vec3>& positions) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices()))
    throw InvalidInput("problems: positions have " + std::to_string(positions.size()) + " entries, the mesh has " +
                       std::to_string(n_vertices()) + " vertices");
  EditProblems p;
  for (Vertex v : touched_) {
    if (positions[v].allFinite()) continue;
    if (p.non_finite++ == 0) p.first_non_finite = v;
  }
  if (p.non_finite > 0) return p;
  p.folded_edges = folds_.count(positions);
  if (multires_ && detail_carried().empty()) p.detail = multires_->problems(positions);
  return p;
}

void require_finite(const EditProblems& problems, std::span<const Eigen::Affine3d> transforms) {
  if (problems.non_finite == 0) return;
  const std::string what = "the deformed mesh has " + std::to_string(problems.non_finite) +
                           " non-finite positions (the first at vertex " + std::to_string(problems.first_non_finite.idx()) + ")";
  double largest = 0.0;  // of the transforms' entries: near 1e308 the products overflow
  for (const Eigen::Affine3d& t : transforms) largest = std::max(largest, t.matrix().cwiseAbs().maxCoeff());
  if (largest > 1e150)
    throw InvalidInput(what + ": the transforms are too large for double precision (an entry of " +
                       json_messages::num(largest) + "); move, rotate and scale by finite amounts well below 1e300");
  throw SolverError(what + ": the system is too ill-conditioned for this support; try a smaller order or support");
}

Mesh deform(const Mesh& mesh, const Edit& edit, EditStats* stats) {
  const EditSolver solver(mesh, edit);
  Mesh out = mesh;
  solver.evaluate(solver.transforms(edit), out.positions());
  require_finite(solver.problems(out.positions()), solver.transforms(edit));
  if (stats) *stats = solver.stats();
  return out;
}

}  // namespace freeform
