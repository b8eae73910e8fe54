// The precomputing object of a whole edit (like geometry-central's HeatMethodDistanceSolver):
// the constructor does all the sparse work once (regions, the deformation model's
// factorization and basis, the multiresolution decomposition); evaluate(transforms) is the
// per-frame call. deform() is the one-shot form. CLI, editor, bindings and benchmarks all go
// through this class, so a deformation model or option is added here and nowhere else.
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/folds.h"
#include "freeform/edit/edit.h"
#include "freeform/mesh/mesh.h"
#include "freeform/model/iterative_model.h"
#include "freeform/multires/multires_solver.h"
#include "freeform/nonlinear/nonlinear_solver.h"
#include "freeform/regions/regions.h"

#include <Eigen/Geometry>

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace freeform {

struct EditStats {
  Deformation deformation = Deformation::Linear;
  BcmStats bcm;                            // assembly, factorization, basis, solver, anisotropy
  std::optional<MultiresStats> multires;   // set with multiresolution
  int isolated_ignored = 0;                // support vertices in no face, kept fixed (edit_regions)
  // Free vertices on an open seam (mesh/seams.h: at the position of another boundary vertex the
  // mesh does not join to them), and the first such pair: the surface may open there.
  int open_seam_vertices = 0;
  std::array<Vertex, 2> open_seam_example{};
  // The precompute's wall and CPU time, whole and per phase (operator_shape with
  // multiresolution, BCM's phases, then model_setup: the detail's encoding and the nonlinear
  // model's setup); the phases add up to the whole.
  PhaseTime precompute;
  std::vector<Phase> phases;
  // Why the edit was solved at a lower order than it asked for (empty: it was not): an order-3
  // system beyond double precision on the support (needle triangles), solved at order 2.
  std::string order_fallback;
};

// Wall times of the last evaluate(), in milliseconds.
struct EditTimings {
  double evaluate_ms = 0;        // the model's frame (linear: the basis product)
  double reconstruction_ms = 0;  // multiresolution detail; 0 without it
};

// What is wrong with a frame (see EditSolver::problems).
struct EditProblems {
  int non_finite = 0;                 // touched vertices with a non-finite position
  Vertex first_non_finite;            // the first of them (invalid if none)
  int folded_edges = 0;               // dihedral angle grew by more than kFoldDegrees (mesh/folds.h)
  MultiresProblems detail;            // flips and overlaps of the detail (multiresolution only)
  bool ok() const { return non_finite == 0 && folded_edges == 0 && detail.ok(); }
};

class EditSolver {
 public:
  // Throws InvalidInput (regions, settings), SolverError (factorization), Cancelled (progress).
  // An order-3 edit whose system fails (SolverError) or whose solve's estimated error exceeds
  // kForwardErrorWarning is solved at order 2, its boundary smoothness capped at C1, and says so
  // in stats().order_fallback; it throws only if order 2 fails too.
  EditSolver(const Mesh& mesh, const Edit& edit, const Progress& progress = {});
  ~EditSolver();
  EditSolver(EditSolver&&) noexcept;
  EditSolver& operator=(EditSolver&&) noexcept;

  const Regions& regions() const { return regions_; }
  const BcmSettings& settings() const { return settings_; }  // the edit's, or the lower order's
  int n_vertices() const { return regions_.n_vertices(); }
  int n_movable() const { return regions_.n_movable(); }  // transforms per frame, in handle order
  Vec3 handle_centroid(int movable) const;                // default pivot of movable handle m
  // The edit's own transforms (manipulator or matrix per movable handle). Throws InvalidInput
  // if `edit` has another number of movable handles than this solver.
  std::vector<Eigen::Affine3d> transforms(const Edit& edit) const;
  // The vertices a frame can change (free and movable-handle vertices), sorted: everything
  // else keeps the positions evaluate() was given.
  const std::vector<Vertex>& touched() const { return touched_; }

  // Writes the touched vertices of `positions` (#V entries; others untouched) for one affine
  // map per movable handle, applied to the rest positions. No allocation, O(support).
  // Uses workspace: call from one thread at a time. Throws InvalidInput on a wrong count,
  // a non-finite transform or a wrong size.
  // The nonlinear model solves cold to convergence (or its iteration cap), stepping `progress`
  // after each iteration (Cancelled: positions untouched).
  void evaluate(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                const Progress& progress = {}) const;
  const EditTimings& last_timings() const { return timings_; }
  // The nonlinear model's iterations of the last frame (null for the linear model).
  const NonlinearState* nonlinear_state() const;
  // The nonlinear model's options (null for the linear model).
  const NonlinearOptions* nonlinear_options() const;

  // The model that iterates (the nonlinear one; with multiresolution MultiresSolver's, on the
  // base), null for the linear model: what DragSession drives on its worker thread. Its
  // iterates are shown with show(). Its state belongs to whoever drives it: evaluate() and a
  // DragSession must not run at once.
  IterativeModel* iterative_model() const;
  // Writes the touched vertices of `positions` for free rows given in free_vertices() order
  // (multiresolution: the base's, its detail added back) and the movable handles moved by
  // `transforms`; no solve. How DragSession shows an iterate of another thread. Throws
  // InvalidInput on wrong sizes.
  void show(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<const BcmSolver::RowMatrixX3d> free_rows,
            VertexData<Vec3>& positions) const;
  // Non-finite positions, folded edges and detail problems of `positions` as written by the
  // last evaluate(). O(support).
  EditProblems problems(const VertexData<Vec3>& positions) const;

  // Why the last evaluate() kept the nonlinear model's solve on the detailed mesh instead of the
  // decomposed one (empty where it did not): the detail re-added to the base flipped or was
  // flattened (MultiresProblems), and the model carrying the detail itself, as without
  // multiresolution, folded no more edges. DragSession shows the decomposed iterates.
  const std::string& detail_carried() const;

  const EditStats& stats() const { return stats_; }
  const BcmSolver& bcm() const;                                   // the linear model's solver
  const MultiresSolver* multires() const { return multires_.get(); }  // null without multires

 private:
  void build(const Mesh& mesh, const Edit& edit, const Progress& progress);
  void carry_failed_detail(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                           const Progress& progress) const;

  Regions regions_;
  BcmSettings settings_;
  std::vector<Vertex> touched_;
  FoldCounter folds_;
  std::unique_ptr<BcmSolver> bcm_;             // plain linear model
  std::unique_ptr<MultiresSolver> multires_;   // either model with detail (owns its solvers)
  std::unique_ptr<IterativeModel> model_;      // plain iterating model (over bcm_'s system)
  std::optional<NonlinearOptions> nonlinear_options_;  // set for the nonlinear model
  // The nonlinear model over the detailed mesh, where multires_ decomposes for it: built on the
  // first frame whose detail fails (detail_carried()).
  struct Carried;
  std::unique_ptr<Carried> carried_;
  EditStats stats_;
  mutable EditTimings timings_;
};

// Throws SolverError naming the first bad vertex if problems.non_finite > 0.
// Throws when a frame produced non-finite positions, naming the cause: transforms too large for
// double precision (InvalidInput) or an ill-conditioned system (SolverError).
void require_finite(const EditProblems& problems, std::span<const Eigen::Affine3d> transforms = {});

// Applies the edit to a copy of the mesh (vertex order and faces kept): EditSolver + one
// evaluate with the edit's own transforms. Throws SolverError on a non-finite result.
Mesh deform(const Mesh& mesh, const Edit& edit, EditStats* stats = nullptr);

}  // namespace freeform
