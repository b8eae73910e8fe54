#include "freeform/edit/drag_session.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <chrono>
#include <exception>
#include <limits>

namespace freeform {
namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

bool same_transforms(std::span<const Eigen::Affine3d> a, std::span<const Eigen::Affine3d> b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].matrix() != b[i].matrix()) return false;
  return true;
}

}  // namespace

DragSession::DragSession(const EditSolver& solver) : solver_(solver), model_(solver.iterative_model()) {
  if (model_) worker_ = std::thread([this] { run(); });
}

DragSession::~DragSession() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    interrupt_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

DragFrame DragSession::frame(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions) {
  if (static_cast<int>(transforms.size()) != solver_.n_movable())
    throw InvalidInput("evaluate: got " + std::to_string(transforms.size()) + " transforms for " +
                       std::to_string(solver_.n_movable()) + " movable handles");
  for (std::size_t m = 0; m < transforms.size(); ++m)
    if (!transforms[m].matrix().allFinite()) throw InvalidInput("evaluate: transform " + std::to_string(m) + " is not finite");
  if (positions.size() != static_cast<std::size_t>(solver_.n_vertices()))
    throw InvalidInput("evaluate: positions have " + std::to_string(positions.size()) + " entries, the mesh has " +
                       std::to_string(solver_.n_vertices()) + " vertices");
  const bool changed = !shown_any_ || !same_transforms(transforms, shown_);
  if (!model_) {
    if (!changed) return {};
    solver_.evaluate(transforms, positions);
    shown_.assign(transforms.begin(), transforms.end());
    shown_any_ = true;
    DragFrame f{true, false, true, {0, 0.0, true, solver_.last_timings().evaluate_ms}};
    f.evaluate_ms = solver_.last_timings().evaluate_ms;
    f.reconstruction_ms = solver_.last_timings().reconstruction_ms;
    return f;
  }
  std::unique_lock lock(mutex_);
  if (changed) {
    pending_.assign(transforms.begin(), transforms.end());
    has_pending_ = true;
    interrupt_ = true;
    wake_.notify_all();
  }
  // The very first frame waits for the worker's start (a basis product, no iteration).
  settled_.wait(lock, [this] { return front_.version > 0 || error_; });
  if (front_.version == 0) throw SolverError("the nonlinear model failed: " + *error_);
  if (!changed && front_.version == shown_version_) {
    const bool predicted = !same_transforms(transforms, front_.transforms);  // the worker is behind
    return {false, predicted, front_.settled && !predicted, front_.state};
  }
  return show(transforms, positions, lock);
}

DragFrame DragSession::show(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                            std::unique_lock<std::mutex>& lock) {
  const auto t0 = Clock::now();
  DragFrame f;
  f.written = true;
  f.state = front_.state;
  f.predicted = !same_transforms(transforms, front_.transforms);
  f.settled = front_.settled && !f.predicted;
  if (f.predicted) {
    linear_now_.resize(model_->n_free(), 3);
    {
      std::lock_guard guard(bcm_mutex_);
      solver_.bcm().evaluate(transforms, linear_now_);
    }
    base_ = front_.x + linear_now_ - front_.linear;
  } else {
    base_ = front_.x;
  }
  shown_version_ = front_.version;
  lock.unlock();
  solver_.show(transforms, base_, positions);
  shown_.assign(transforms.begin(), transforms.end());
  shown_any_ = true;
  f.reconstruction_ms = solver_.last_timings().reconstruction_ms;
  f.evaluate_ms = ms_since(t0) - f.reconstruction_ms;
  return f;
}

DragFrame DragSession::finish(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                              const Progress& progress) {
  DragFrame f = frame(transforms, positions);
  if (!model_) return f;
  std::unique_lock lock(mutex_);
  const auto done = [&] { return error_ || (front_.settled && same_transforms(transforms, front_.transforms)); };
  const int cap = std::max(model_->max_iterations(), 1);
  while (!settled_.wait_for(lock, std::chrono::milliseconds(20), done)) {
    const double fraction = std::min(1.0, static_cast<double>(front_.state.iterations) / cap);
    lock.unlock();
    progress.step("nonlinear", fraction);
    lock.lock();
  }
  if (error_) throw SolverError("the nonlinear model failed: " + *error_);
  if (front_.version == shown_version_) return {false, false, true, front_.state};
  return show(transforms, positions, lock);
}

std::optional<std::string> DragSession::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void DragSession::run() {
  std::unique_lock lock(mutex_);
  std::vector<Eigen::Affine3d> current;
  RowMatrixX3d linear(model_->n_free(), 3);
  bool warm = false, settled = true;
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || has_pending_ || !settled; });
    if (stop_) return;
    const bool restart = has_pending_;
    if (restart) {
      current.swap(pending_);
      has_pending_ = false;
      interrupt_ = false;
    }
    lock.unlock();
    try {
      if (restart) {
        {
          std::lock_guard guard(bcm_mutex_);
          solver_.bcm().evaluate(current, linear);
        }
        model_->start(current, warm, &linear);
        warm = true;
        settled = false;
      } else {
        const NonlinearState& s = model_->iterate(1, std::numeric_limits<double>::infinity(), &interrupt_);
        settled = s.converged || s.iterations >= model_->max_iterations();
      }
      back_.transforms = current;
      back_.x = model_->free_positions();
      back_.linear = linear;
      back_.state = model_->state();
      back_.settled = settled;
    } catch (const std::exception& e) {
      lock.lock();
      error_ = e.what();
      settled = true;
      settled_.notify_all();
      continue;
    }
    lock.lock();
    if (restart) error_.reset();
    back_.version = front_.version + 1;
    std::swap(front_, back_);
    settled_.notify_all();
  }
}

}  // namespace freeform
