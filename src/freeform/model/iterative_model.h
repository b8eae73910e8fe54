// The seam between an edit and a deformation model that iterates (docs/architecture.md, "Adding
// a model"). Its constructor is the precompute (over linear BCM's kept system, see
// IterativeModelFactory); start() takes the transforms of a frame, iterate() runs within an
// iteration count and a time budget and can be interrupted, and calling iterate() again refines
// where it stopped. EditSolver owns the model, or MultiresSolver does when the model deforms the
// smooth base and the detail is added to each iterate shown; EditSolver::evaluate solves cold
// to convergence (solve()), DragSession drives a drag on a worker thread.
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <Eigen/Geometry>

#include <atomic>
#include <functional>
#include <memory>
#include <span>

namespace freeform {

// How far the iterations since the last start() got.
struct NonlinearState {
  int iterations = 0;      // global steps (back-substitutions)
  // Largest vertex move of the last iteration / support extent (at the cap: of the iterate returned).
  double step = 0;
  bool converged = false;  // step <= tolerance
  double ms = 0;           // wall time of the iterations so far
};

class IterativeModel {
 public:
  using RowMatrixX3d = BcmSolver::RowMatrixX3d;

  IterativeModel() = default;
  virtual ~IterativeModel() = default;
  IterativeModel(const IterativeModel&) = delete;
  IterativeModel& operator=(const IterativeModel&) = delete;

  virtual int n_free() const = 0;
  virtual int max_iterations() const = 0;  // the cap of one solve
  // Starts iterating for one affine map per movable handle. Cold: from the model's own start.
  // Warm: from the last iterate, moved by the change of `linear` (linear BCM's free rows for
  // these transforms; null: none) since the last start when both have one. Throws InvalidInput
  // on a wrong count or a non-finite transform.
  virtual void start(std::span<const Eigen::Affine3d> transforms, bool warm, const RowMatrixX3d* linear) = 0;
  // Runs iterations until converged, `max_iterations` more, `budget_ms` spent, or `interrupt`
  // (checked after each global step; null: none) is set. The iterate stays valid.
  virtual const NonlinearState& iterate(int max_iterations, double budget_ms, const std::atomic<bool>* interrupt) = 0;
  virtual const NonlinearState& state() const = 0;
  // The current iterate's free rows (P x 3, BcmSolver::free_vertices() order).
  virtual Eigen::Ref<const RowMatrixX3d> free_positions() const = 0;

  // Iterations from the last start() to convergence or the cap, stepping `progress`
  // ("nonlinear", iterations / cap) after each: a caller can cancel a long solve there.
  void run(const Progress& progress = {});
  // One cold solve (start + run); writes the free rows to `out` (P x 3). Throws InvalidInput on
  // a wrong size; Cancelled leaves `out` untouched.
  void solve(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<RowMatrixX3d> out, const Progress& progress = {});
};

// Builds an iterating model over `linear` (built with keep_system from the same mesh and
// regions) that keeps the shape `rest` (#V entries). How a model is handed to MultiresSolver,
// which builds the system and the smooth base it runs on (MultiresOptions::model).
using IterativeModelFactory = std::function<std::unique_ptr<IterativeModel>(
    const Mesh& mesh, const Regions& regions, BcmSolver& linear, const VertexData<Vec3>& rest)>;

}  // namespace freeform
