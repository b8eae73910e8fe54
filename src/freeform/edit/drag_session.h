// An interactive drag over an EditSolver (the editor, the Blender add-on): frame(transforms)
// writes what to show now and never waits for the nonlinear model. Its iterations run on a
// worker thread; a frame shows the newest iterate moved by linear BCM's change from the
// iterate's transforms to the frame's (a first-order prediction; exact once the worker has
// caught up), so the handle follows at the basis product's speed however long an iteration
// takes. The worker restarts (warm) from new transforms after its current global step and
// keeps iterating when they rest, until converged or the iteration cap. The linear model
// evaluates on the calling thread, as EditSolver::evaluate.
#pragma once

#include "freeform/common/progress.h"
#include "freeform/edit/edit_solver.h"

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <thread>
#include <vector>

namespace freeform {

struct DragFrame {
  bool written = false;    // positions were written (false: nothing new since the last frame)
  bool predicted = false;  // the iterate is older than the transforms: moved by linear BCM's change
  bool settled = true;     // the model converged or hit its cap for these transforms (linear: true)
  NonlinearState state;    // of the iterate shown (linear: converged, 0 iterations)
  double evaluate_ms = 0;        // this call's basis product or prediction
  double reconstruction_ms = 0;  // multiresolution detail; 0 without it
};

class DragSession {
 public:
  // `solver` must outlive the session and, while it exists, get no evaluate() (problems() of
  // written positions is fine).
  explicit DragSession(const EditSolver& solver);
  ~DragSession();  // stops the worker after its current global step and joins it
  DragSession(const DragSession&) = delete;
  DragSession& operator=(const DragSession&) = delete;

  // Writes the touched vertices of `positions` (#V) for one transform per movable handle, if
  // the transforms or the worker's iterate changed since the last frame (else `written` is
  // false and positions are left alone). Never waits for an iteration. Throws InvalidInput
  // on a wrong count, non-finite transforms or a wrong size.
  DragFrame frame(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions);
  // Blocks until the worker settled for the last frame's transforms, then writes like frame()
  // (a final result; tests). The linear model returns at once. While waiting, `progress` is
  // checked every few milliseconds (Python's Ctrl-C); Cancelled leaves positions alone and
  // the worker iterating.
  DragFrame finish(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                   const Progress& progress = {});
  // The worker's error, if an iteration threw (the session then shows its last iterate).
  std::optional<std::string> error() const;

 private:
  using RowMatrixX3d = BcmSolver::RowMatrixX3d;
  // An iterate with the transforms it belongs to and linear BCM at those transforms.
  struct Iterate {
    std::vector<Eigen::Affine3d> transforms;
    RowMatrixX3d x, linear;
    NonlinearState state;
    bool settled = false;
    std::uint64_t version = 0;
  };

  const EditSolver& solver_;
  IterativeModel* model_ = nullptr;  // null: the linear model, no worker
  std::vector<Eigen::Affine3d> shown_;  // transforms of the last written frame
  std::uint64_t shown_version_ = 0;     // iterate version of the last written frame
  bool shown_any_ = false;
  RowMatrixX3d base_, linear_now_;      // the frame thread's workspace

  mutable std::mutex mutex_;
  std::condition_variable wake_;     // worker: new transforms, stop, or settled changed
  std::condition_variable settled_;  // finish(): the published iterate settled
  // New transforms for the worker; swapped with its own, so no frame allocates.
  std::vector<Eigen::Affine3d> pending_;
  bool has_pending_ = false;
  std::atomic<bool> interrupt_{false};  // has_pending_: end the current iteration early
  bool stop_ = false;
  Iterate front_;  // published (mutex_)
  Iterate back_;   // the worker's
  std::optional<std::string> error_;
  std::mutex bcm_mutex_;  // BcmSolver::evaluate shares workspace above kStackHandles handles
  std::thread worker_;

  void run();
  DragFrame show(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                 std::unique_lock<std::mutex>& lock);
};

}  // namespace freeform
