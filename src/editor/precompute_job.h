// The background precomputation of the editor (issue 4): builds the edit's EditSolver on one
// worker thread from an immutable snapshot, so the UI keeps
// drawing the old result meanwhile. Progress and errors are read from the UI thread; nothing
// is ever thrown into it. A newer request cancels and supersedes the running one.
#pragma once

#include "freeform/edit/edit_solver.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/mesh.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace freeform::editor {

// Wall times of one display update, in milliseconds.
struct FrameTimings {
  double evaluate_ms = 0;        // the BCM basis product (multires: its base) or the prediction
  double reconstruction_ms = 0;  // multires detail reconstruction; 0 without multires
  double total_ms = 0;           // the whole update (copies and transforms included)
  bool evaluated = false;        // false: nothing changed, nothing was computed
  // The nonlinear model (DragSession): iterations and last step of the iterate shown, whether
  // it converged for these transforms (always true for the linear model), and whether the
  // display is a prediction from an iterate of older transforms.
  int iterations = 0;
  double residual = 0;
  bool converged = true;
  bool predicted = false;
};

struct PrecomputeRequest {
  std::shared_ptr<const Mesh> rest;  // the rest mesh, shared and never modified
  Edit edit;                         // regions and settings (transforms are not used)
  std::vector<int> handle_ids;       // stable id of each edit handle, in edit order
  std::uint64_t tag = 0;             // the caller's version stamp, kept by the solver
  // Called on the worker at every progress report, before the cancel check (tests use it to
  // hold the worker at a known stage). Must not call back into the job.
  std::function<void(std::string_view stage, double fraction)> on_progress;
};

// A finished precomputation: immutable after construction. Frames go through a DragSession
// over solver() (one per document, see Document::update_display).
class PreparedSolver {
 public:
  // The edit's EditSolver (as deform() builds it). Throws like it (InvalidInput, SolverError,
  // Cancelled, ...).
  PreparedSolver(const PrecomputeRequest& request, const Progress& progress);

  const EditSolver& solver() const { return *solver_; }
  bool multiresolution() const { return solver_->stats().multires.has_value(); }
  // Multiresolution with the nonlinear model where the detail overhangs its base: the model
  // carries the detail itself (EditSolver, docs/nonlinear.md).
  bool detail_by_model() const { return multiresolution() && solver_->stats().multires->detail_by_model; }
  int n_movable() const { return solver_->n_movable(); }
  const BcmStats& stats() const { return solver_->stats().bcm; }
  const std::vector<Vertex>& touched() const { return solver_->touched(); }
  // Handle id of each movable index (the order evaluate() expects transforms in).
  const std::vector<int>& movable_ids() const { return movable_ids_; }
  std::uint64_t tag() const { return tag_; }
  const std::shared_ptr<const Mesh>& rest() const { return rest_; }

 private:
  std::shared_ptr<const Mesh> rest_;
  std::vector<int> movable_ids_;
  std::uint64_t tag_ = 0;
  std::unique_ptr<EditSolver> solver_;
};

enum class JobState { Idle, Running, Finished, Failed, Cancelled };

struct JobStatus {
  JobState state = JobState::Idle;
  double fraction = 0;    // of the newest request, in [0, 1]
  std::string stage;      // "queued", "assembly", "factorization", "basis", "refinement", "detail", "done"
  std::string error;      // Failed: what went wrong (the solver's message)
  std::uint64_t tag = 0;  // of the newest request
};

class PrecomputeJob {
 public:
  PrecomputeJob() = default;
  ~PrecomputeJob();  // cancels, then joins the worker
  PrecomputeJob(const PrecomputeJob&) = delete;
  PrecomputeJob& operator=(const PrecomputeJob&) = delete;

  // Queues `request`; a running or queued older one is cancelled (a result that finishes
  // anyway is discarded). Never blocks on the computation. Starts the worker on first use.
  void start(PrecomputeRequest request);
  // Drops the queued request and cancels the running one at its next checkpoint. The state
  // becomes Cancelled (once the worker stops); solver() keeps the last finished solver.
  void cancel();
  // Blocks until no request is queued or running.
  void wait();

  bool running() const;  // a request is queued or running
  JobStatus status() const;
  // The newest successfully finished solver (kept when later requests fail or are cancelled).
  std::shared_ptr<const PreparedSolver> solver() const;
  // Incremented each time solver() changes (cheap per-frame poll).
  std::uint64_t generation() const;

 private:
  mutable std::mutex mutex_;
  std::condition_variable wake_;  // worker: a request is queued or stop_
  std::condition_variable idle_;  // wait(): the worker became idle
  std::optional<PrecomputeRequest> pending_;
  bool busy_ = false;
  bool stop_ = false;
  std::atomic<bool> cancel_{false};
  JobStatus status_;
  std::shared_ptr<const PreparedSolver> solver_;
  std::uint64_t generation_ = 0;
  std::thread thread_;

  void run();
  void compute(PrecomputeRequest& request, std::unique_lock<std::mutex>& lock);
};

}  // namespace freeform::editor
