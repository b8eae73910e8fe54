// Per-frame parallel loops that never wait for a thread that is not running (issue 13). An
// OpenMP team ends at a barrier: when another process has one of the two cores, the frame
// waits a scheduler slice for the descheduled team member. Here the caller takes chunks from an
// atomic counter itself, sleeping pool workers join when they get to run, and at the end the
// caller waits only for chunks a worker has already taken (so is running or was preempted in).
// Workers sleep on a condition variable between loops: no spinning threads are left behind.
// One loop at a time uses the pool; a loop started while another runs (a second thread) runs
// on its caller alone. After a loop whose caller waited for a preempted worker, the next loops
// run on the caller alone, for exponentially more loops on each repeated stall (a busy machine
// then rarely sees such a wait; bench/bench_editor_frame busy measures the 99th percentile).
#pragma once

#include <cstddef>
#include <functional>

namespace freeform {

// The body as a pointer and a plain function: a std::function of a lambda with more than two
// captures allocates, once per loop of every frame.
struct ParallelBody {
  const void* object;
  void (*call)(const void* object, std::ptrdiff_t begin, std::ptrdiff_t end);
};
void parallel_for(std::ptrdiff_t n, std::ptrdiff_t grain, ParallelBody body);

// Calls body(begin, end) over [0, n) in chunks of about `grain` rows (at least one chunk per
// pool thread when n allows it). Below 2 * grain rows, or with one hardware thread, it is a
// plain call body(0, n) on the caller. body must not throw. No allocation.
template <class F>
void parallel_for(std::ptrdiff_t n, std::ptrdiff_t grain, const F& body) {
  parallel_for(n, grain, ParallelBody{&body, [](const void* f, std::ptrdiff_t begin, std::ptrdiff_t end) {
                                        (*static_cast<const F*>(f))(begin, end);
                                      }});
}

// Forgets the stalls that made parallel_for run its loops on the caller alone (above): for a
// thread of this process that ran beside the pool and has ended (the ordering ahead,
// run_tasks' threads). Its own work preempted the workers, not another process; without this
// the precompute's next thousands of loops, its factorization among them, ran on one core.
void forget_parallel_stalls();

// Pool threads besides the caller (hardware threads - 1, at least 0; FREEFORM_THREADS=N caps
// the total at N).
int parallel_workers();

// The threads this process may keep busy: the hardware's, capped by FREEFORM_THREADS (or
// OMP_NUM_THREADS). The first call also caps OpenBLAS's and OpenMP's teams at FREEFORM_THREADS
// when it is set, so that the pool, the BLAS and CHOLMOD never run more threads than asked.
int thread_budget();

// OpenBLAS's thread count (0 if the BLAS is not OpenBLAS).
int blas_threads();

// OpenBLAS's thread count set to n (at most thread_budget()) for a scope, then restored: 1 where
// several threads call the BLAS at once. No effect if the BLAS is not OpenBLAS. Raising it above
// the count OpenBLAS started with starts threads that need work buffers of their own.
class BlasThreads {
 public:
  explicit BlasThreads(int n);
  ~BlasThreads();
  BlasThreads(const BlasThreads&) = delete;
  BlasThreads& operator=(const BlasThreads&) = delete;

 private:
  int saved_;
};

// Runs task(0) .. task(n - 1), each once, on up to thread_budget() threads (the caller is one of
// them): coarse tasks of seconds, such as ordering the parts of a graph. Unlike parallel_for it
// starts its own threads, so a long task never holds the per-frame pool. The first exception
// thrown by a task is rethrown after all have finished.
void run_tasks(int n, const std::function<void(int)>& task);

// CPU time (ms) that the threads run_tasks started have spent on this thread's calls so far:
// with PhaseClock::thread_cpu_ms(), what a thread's work cost in all.
double helper_cpu_ms();

}  // namespace freeform
