#include "editor/precompute_job.h"

#include <exception>
#include <new>

namespace freeform::editor {
PreparedSolver::PreparedSolver(const PrecomputeRequest& request, const Progress& progress)
    : rest_(request.rest), tag_(request.tag) {
  if (!rest_) throw InvalidInput("no mesh to precompute on");
  if (request.handle_ids.size() != request.edit.handles.size())
    throw InvalidInput("the request names " + std::to_string(request.handle_ids.size()) + " handle ids for " +
                       std::to_string(request.edit.handles.size()) + " handles");
  for (std::size_t i = 0; i < request.edit.handles.size(); ++i)
    if (request.edit.handles[i].movable) movable_ids_.push_back(request.handle_ids[i]);
  progress.check();
  solver_ = std::make_unique<EditSolver>(*rest_, request.edit, progress);
}

PrecomputeJob::~PrecomputeJob() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    pending_.reset();
    cancel_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void PrecomputeJob::start(PrecomputeRequest request) {
  {
    std::lock_guard lock(mutex_);
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
    status_ = JobStatus{JobState::Running, 0.0, "queued", {}, request.tag};
    pending_ = std::move(request);
    if (busy_) cancel_ = true;
  }
  wake_.notify_all();
}

void PrecomputeJob::cancel() {
  std::optional<PrecomputeRequest> dropped;  // destroyed outside the lock
  std::lock_guard lock(mutex_);
  dropped = std::move(pending_);
  pending_.reset();
  if (busy_) {
    cancel_ = true;  // the worker sets Cancelled when it stops
  } else if (status_.state == JobState::Running) {
    status_.state = JobState::Cancelled;
    idle_.notify_all();
  }
}

void PrecomputeJob::wait() {
  std::unique_lock lock(mutex_);
  idle_.wait(lock, [this] { return !busy_ && !pending_; });
}

bool PrecomputeJob::running() const {
  std::lock_guard lock(mutex_);
  return busy_ || pending_.has_value();
}

JobStatus PrecomputeJob::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

std::shared_ptr<const PreparedSolver> PrecomputeJob::solver() const {
  std::lock_guard lock(mutex_);
  return solver_;
}

std::uint64_t PrecomputeJob::generation() const {
  std::lock_guard lock(mutex_);
  return generation_;
}

void PrecomputeJob::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stop_ || pending_.has_value(); });
    if (stop_) return;
    PrecomputeRequest request = std::move(*pending_);
    pending_.reset();
    cancel_ = false;
    busy_ = true;
    status_ = JobStatus{JobState::Running, 0.0, "starting", {}, request.tag};
    compute(request, lock);
    busy_ = false;
    idle_.notify_all();
  }
}

// Runs one request with the lock released; returns with it held and status_ updated.
void PrecomputeJob::compute(PrecomputeRequest& request, std::unique_lock<std::mutex>& lock) {
  lock.unlock();
  std::shared_ptr<const PreparedSolver> result;
  std::string error;
  bool cancelled = false;
  try {
    Progress progress;
    progress.cancel = &cancel_;
    progress.report = [&](std::string_view stage, double fraction) {
      if (request.on_progress) request.on_progress(stage, fraction);
      std::lock_guard guard(mutex_);
      if (pending_) return;  // the status belongs to the queued request now
      status_.stage = std::string(stage);
      status_.fraction = fraction;
    };
    result = std::make_shared<const PreparedSolver>(request, progress);
  } catch (const Cancelled&) {
    cancelled = true;
  } catch (const std::bad_alloc&) {
    error = "out of memory while precomputing: paint a smaller support region";
  } catch (const std::exception& e) {
    error = e.what();
  } catch (...) {
    error = "unknown error while precomputing";
  }
  lock.lock();
  if (pending_) {
    // Superseded: the queued request owns the status; a late result is discarded below.
  } else if (cancelled || cancel_) {
    status_.state = JobState::Cancelled;
  } else if (!error.empty()) {
    status_.state = JobState::Failed;
    status_.error = std::move(error);
  } else {
    status_.state = JobState::Finished;
    status_.stage = "done";
    status_.fraction = 1.0;
    solver_ = result;
    ++generation_;
  }
  if (result && solver_ != result) {  // free a discarded solver without holding the lock
    lock.unlock();
    result.reset();
    lock.lock();
  }
}

}  // namespace freeform::editor
