#include "freeform/common/parallel.h"

#include "freeform/common/held_threads.h"
#include "freeform/common/phase_clock.h"

#include <dlfcn.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

namespace freeform {
namespace {

constexpr std::chrono::microseconds kSpin{50};

// Set by forget_parallel_stalls(), applied by the pool's next loop. Outside the pool: a
// detached thread (an ordering ahead that outlives its precompute) may set it after the pool,
// a function-local static, was destroyed at exit.
std::atomic<bool> forget_stalls{false};

// OpenBLAS and libgomp read their own variables when they load; FREEFORM_THREADS reaches
// them through their setters, looked up at run time so that neither is a link dependency.
void cap_library_threads(int n) {
  for (const char* name : {"openblas_set_num_threads", "omp_set_num_threads"})
    if (void* f = dlsym(RTLD_DEFAULT, name)) reinterpret_cast<void (*)(int)>(f)(n);
}

int threads_from_environment() {
  const int total = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  for (const char* name : {"FREEFORM_THREADS", "OMP_NUM_THREADS"}) {
    const char* value = std::getenv(name);
    if (!value) continue;
    const int n = std::atoi(value);
    if (n <= 0) continue;
    if (std::string_view(name) == "FREEFORM_THREADS") cap_library_threads(std::min(total, n));
    return std::min(total, n);
  }
  return total;
}

class Pool {
 public:
  static Pool& get() {
    static Pool pool;
    return pool;
  }
  int workers() const { return static_cast<int>(threads_.size()); }

  // False if another loop holds the pool or the pool is backing off after a stall (the caller
  // then runs alone).
  bool run(std::ptrdiff_t n, std::ptrdiff_t chunk, ParallelBody body) {
    const std::unique_lock busy(busy_, std::try_to_lock);
    if (!busy.owns_lock()) return false;
    if (forget_stalls.exchange(false, std::memory_order_relaxed)) {
      solo_loops_ = 0;
      backoff_ = kMinBackoff;
    }
    if (solo_loops_ > 0) {
      --solo_loops_;
      return false;
    }
    const auto chunks = static_cast<std::uint32_t>((n + chunk - 1) / chunk);
    if (chunks > kMaxChunks) return false;
    // Never more threads than the budget: those held beside the caller (the ordering ahead and
    // its parts, held_threads.h) take workers' seats.
    const int seats = threads_free() - 1;
    if (seats <= 0) return false;
    seats_.store(seats, std::memory_order_relaxed);
    const auto start = Clock::now();
    body_.store(body.object, std::memory_order_relaxed);
    call_.store(body.call, std::memory_order_relaxed);
    rows_.store(n, std::memory_order_relaxed);
    chunk_.store(chunk, std::memory_order_relaxed);
    chunks_.store(chunks, std::memory_order_relaxed);  // for done_: workers take by next_'s copy
    done_.store(0, std::memory_order_relaxed);
    std::uint32_t generation = 0;
    bool sleeping = false;
    {
      const std::lock_guard lock(mutex_);
      generation = ++generation_;
      next_.store(std::uint64_t{generation} << 32 | std::uint64_t{chunks} << 16, std::memory_order_release);
      published_.store(generation, std::memory_order_release);
      sleeping = sleepers_ > 0;
    }
    if (sleeping) wake_.notify_all();
    work(generation);
    // Only chunks a worker has taken remain: it is running them (or was preempted inside one).
    const auto own = Clock::now();
    for (std::uint32_t d = done_.load(std::memory_order_acquire); d != chunks; d = done_.load(std::memory_order_acquire))
      done_.wait(d, std::memory_order_acquire);
    // A wait longer than the caller's own share (and than kStall) means a worker was preempted
    // inside a chunk: another process wants the core. Run alone for the next `backoff_` loops,
    // doubling it on each stall, so a loaded machine sees such a stall ever more rarely; loops
    // that run clean shrink it again.
    const auto waited = Clock::now() - own;
    if (waited > std::max<Clock::duration>(kStall, own - start)) {
      solo_loops_ = backoff_;
      backoff_ = std::min(2 * backoff_, kMaxBackoff);
    } else {
      backoff_ = std::max(backoff_ / 2, kMinBackoff);
    }
    return true;
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::microseconds kStall{300};
  static constexpr int kMinBackoff = 64, kMaxBackoff = 4096;
  std::mutex busy_;   // one loop at a time; guards solo_loops_ and backoff_
  int solo_loops_ = 0;
  int backoff_ = kMinBackoff;
  std::mutex mutex_;  // generation_, stop_
  std::condition_variable wake_;
  std::uint32_t generation_ = 0;
  int sleepers_ = 0;  // workers waiting on wake_
  bool stop_ = false;
  std::atomic<std::uint32_t> published_{0};  // generation_, read by spinning workers
  // Workers that may join the current loop. A worker late for a loop may take a seat of the
  // next: that loop then runs on fewer threads, never on more.
  std::atomic<int> seats_{0};
  // The current loop. next_ = generation << 32 | chunk count << 16 | next chunk: the count
  // travels with the generation, because a worker still in the previous loop that compared
  // its stale index with chunks_ after the caller had stored the next loop's count could take
  // a chunk that does not exist and run it with a mix of both loops' fields. The other fields
  // are read only after a chunk of that generation was taken, which keeps the loop from
  // ending meanwhile.
  static constexpr std::uint32_t kMaxChunks = 0xFFFF;
  std::atomic<std::uint64_t> next_{0};
  std::atomic<std::uint32_t> chunks_{0}, done_{0};
  std::atomic<const void*> body_{nullptr};
  std::atomic<void (*)(const void*, std::ptrdiff_t, std::ptrdiff_t)> call_{nullptr};
  std::atomic<std::ptrdiff_t> rows_{0}, chunk_{1};
  std::vector<std::thread> threads_;

  Pool() {
    const int n = thread_budget() - 1;
    try {
      for (int i = 0; i < n; ++i) threads_.emplace_back([this] { sleep_and_work(); });
    } catch (const std::system_error&) {
      // No thread to be had (an address-space limit leaves no room for its stack): the loops
      // run on the workers that did start, or on the caller alone.
    }
  }
  ~Pool() {
    {
      const std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : threads_) t.join();
  }

  bool take(std::uint32_t generation, std::uint32_t& chunk) {
    std::uint64_t v = next_.load(std::memory_order_acquire);
    for (;;) {
      if (static_cast<std::uint32_t>(v >> 32) != generation) return false;
      const auto index = static_cast<std::uint32_t>(v & kMaxChunks);
      if (index >= static_cast<std::uint32_t>((v >> 16) & kMaxChunks)) return false;
      if (next_.compare_exchange_weak(v, v + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
        chunk = index;
        return true;
      }
    }
  }

  void work(std::uint32_t generation) {
    std::uint32_t c = 0;
    while (take(generation, c)) {
      const std::ptrdiff_t size = chunk_.load(std::memory_order_relaxed), n = rows_.load(std::memory_order_relaxed);
      const std::ptrdiff_t begin = static_cast<std::ptrdiff_t>(c) * size;
      call_.load(std::memory_order_relaxed)(body_.load(std::memory_order_relaxed), begin, std::min(n, begin + size));
      if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == chunks_.load(std::memory_order_relaxed))
        done_.notify_all();
    }
  }

  // After a loop a worker polls for the next one for kSpin (a frame runs several loops back to
  // back: waking a sleeping thread costs more than a short loop), then sleeps.
  void sleep_and_work() {
    std::uint32_t seen = 0;
    for (;;) {
      const auto until = std::chrono::steady_clock::now() + kSpin;
      std::uint32_t now = published_.load(std::memory_order_acquire);
      for (int i = 0; now == seen; ++i) {
        if (i % 64 == 63 && std::chrono::steady_clock::now() > until) break;
        std::this_thread::yield();
        now = published_.load(std::memory_order_acquire);
      }
      if (now == seen) {
        std::unique_lock lock(mutex_);
        ++sleepers_;
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        --sleepers_;
        if (stop_) return;
        now = generation_;
      }
      seen = now;
      if (seats_.fetch_sub(1, std::memory_order_acq_rel) > 0) work(seen);
    }
  }
};

}  // namespace

int parallel_workers() { return Pool::get().workers(); }

int thread_budget() {
  static const int n = threads_from_environment();
  return n;
}

int blas_threads() {
  thread_budget();  // applies FREEFORM_THREADS first
  void* f = dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
  return f ? reinterpret_cast<int (*)()>(f)() : 0;
}

namespace {
thread_local double helpers_cpu = 0;

void set_blas_threads(int n) {
  static void* const f = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
  if (f && n > 0) reinterpret_cast<void (*)(int)>(f)(n);
}
}  // namespace

BlasThreads::BlasThreads(int n) : saved_(blas_threads()) {
  if (saved_ > 0 && n != saved_) set_blas_threads(std::clamp(n, 1, thread_budget()));
}

BlasThreads::~BlasThreads() {
  if (saved_ > 0 && blas_threads() != saved_) set_blas_threads(saved_);
}

double helper_cpu_ms() { return helpers_cpu; }

void forget_parallel_stalls() { forget_stalls.store(true, std::memory_order_relaxed); }

void run_tasks(int n, const std::function<void(int)>& task) {
  std::atomic<int> next{0};
  std::atomic<double> cpu{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  const auto work = [&] {
    for (int i = next++; i < n; i = next++) {
      try {
        task(i);
      } catch (...) {
        const std::lock_guard lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> threads;
  // Besides the caller, the threads the budget leaves free, less one for the pool's caller (the
  // caller of this, or the thread it runs beside); each holds its seat while it runs.
  const int helpers = std::min(n, threads_free()) - 1;
  for (int t = 0; t < helpers; ++t) {
    try {
      threads.emplace_back([&, held = std::make_shared<HeldThread>()] {
        const double start = PhaseClock::thread_cpu_ms();
        work();
        const double used = PhaseClock::thread_cpu_ms() - start;
        for (double c = cpu.load(); !cpu.compare_exchange_weak(c, c + used);) {
        }
      });
    } catch (const std::system_error&) {
      break;  // no thread to be had: the ones started and the caller do the rest
    }
  }
  work();
  for (std::thread& t : threads) t.join();
  if (!threads.empty()) forget_parallel_stalls();  // they made the pool's workers stall, not another process
  helpers_cpu += cpu.load();
  if (error) std::rethrow_exception(error);
}

void parallel_for(std::ptrdiff_t n, std::ptrdiff_t grain, ParallelBody body) {
  if (n <= 0) return;
  grain = std::max<std::ptrdiff_t>(grain, 1);
  Pool& pool = Pool::get();
  if (n < 2 * grain || pool.workers() == 0) {
    body.call(body.object, 0, n);
    return;
  }
  // About four chunks per thread: a preempted worker holds back at most a quarter of its share.
  const std::ptrdiff_t chunk = std::max(grain, (n + 4 * (pool.workers() + 1) - 1) / (4 * (pool.workers() + 1)));
  if (!pool.run(n, chunk, body)) body.call(body.object, 0, n);
}

}  // namespace freeform
