// parallel_for (common/parallel.h): every index exactly once, for any size and grain, also when
// two threads start loops at once (one of them then runs alone) and after many loops in a row
// (generations of the pool's job slot). run_tasks: every task once on up to thread_budget()
// threads, the first exception rethrown after all tasks ran, its threads' CPU time counted.
// Both: never more threads than the budget with the threads held beside them (held_threads.h).
#include "freeform/common/parallel.h"

#include "freeform/common/held_threads.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using freeform::parallel_for;

namespace {

void expect_each_index_once(std::ptrdiff_t n, std::ptrdiff_t grain) {
  std::vector<std::atomic<int>> hits(static_cast<std::size_t>(n));
  parallel_for(n, grain, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    ASSERT_LE(0, lo);
    ASSERT_LT(lo, hi);
    ASSERT_LE(hi, n);
    for (std::ptrdiff_t i = lo; i < hi; ++i) hits[static_cast<std::size_t>(i)].fetch_add(1);
  });
  for (std::ptrdiff_t i = 0; i < n; ++i) ASSERT_EQ(hits[static_cast<std::size_t>(i)].load(), 1) << "n " << n << " i " << i;
}

// The threads that ran a loop of 64 chunks of 1 ms each.
std::set<std::thread::id> threads_of_a_loop() {
  std::mutex m;
  std::set<std::thread::id> ids;
  parallel_for(64, 1, [&](std::ptrdiff_t, std::ptrdiff_t) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const std::lock_guard lock(m);
    ids.insert(std::this_thread::get_id());
  });
  return ids;
}

// Holds all of the budget but the caller's thread.
std::vector<std::unique_ptr<freeform::HeldThread>> hold_all_but_one() {
  std::vector<std::unique_ptr<freeform::HeldThread>> held;
  for (int i = 1; i < freeform::thread_budget(); ++i) held.push_back(std::make_unique<freeform::HeldThread>());
  return held;
}

}  // namespace

TEST(ParallelFor, EveryIndexExactlyOnce) {
  for (std::ptrdiff_t n : {0, 1, 7, 100, 4095, 4096, 4097, 100000})
    for (std::ptrdiff_t grain : {1, 64, 2048, 1000000}) expect_each_index_once(n, grain);
  EXPECT_GE(freeform::parallel_workers(), 0);
}

TEST(ParallelFor, ManyLoopsInARowAndFromTwoThreadsAtOnce) {
  for (int round = 0; round < 2000; ++round) expect_each_index_once(5000 + round % 7, 100);
  std::thread other([] {
    for (int round = 0; round < 500; ++round) expect_each_index_once(20000, 50);
  });
  for (int round = 0; round < 500; ++round) expect_each_index_once(30000, 70);
  other.join();
}

// Back-to-back loops whose chunk counts alternate (3 and 8 chunks): a worker finishing the
// last chunk of a short loop must not take "chunk 3" of it once the next loop's count is out.
TEST(ParallelFor, LoopsWithAlternatingChunkCounts) {
  for (int round = 0; round < 20000; ++round) expect_each_index_once(round % 2 == 0 ? 250 : 5000, 100);
}

// A sum as the editor's reductions do it: a local per chunk, one atomic add per chunk.
TEST(ParallelFor, ChunkReductionsAddUp) {
  std::atomic<long long> sum{0};
  const std::ptrdiff_t n = 1 << 20;
  parallel_for(n, 1000, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    long long local = 0;
    for (std::ptrdiff_t i = lo; i < hi; ++i) local += i;
    sum += local;
  });
  EXPECT_EQ(sum.load(), static_cast<long long>(n) * (n - 1) / 2);
}

TEST(RunTasks, EveryTaskOnceAndTheFirstErrorRethrown) {
  EXPECT_GE(freeform::thread_budget(), 1);
  for (int n : {0, 1, 3, 64}) {
    std::vector<std::atomic<int>> hits(static_cast<std::size_t>(n));
    freeform::run_tasks(n, [&](int i) { hits[static_cast<std::size_t>(i)].fetch_add(1); });
    for (int i = 0; i < n; ++i) EXPECT_EQ(hits[static_cast<std::size_t>(i)].load(), 1) << n << " " << i;
  }
  std::atomic<int> ran{0};
  EXPECT_THROW(freeform::run_tasks(8,
                                   [&](int i) {
                                     ++ran;
                                     if (i % 3 == 1) throw std::runtime_error("task " + std::to_string(i));
                                   }),
               std::runtime_error);
  EXPECT_EQ(ran.load(), 8);
}

TEST(RunTasks, CountsItsThreadsCpuTimeForTheCaller) {
  if (freeform::thread_budget() < 2) GTEST_SKIP() << "one thread: the caller runs every task";
  const double before = freeform::helper_cpu_ms();
  freeform::run_tasks(2, [](int) {
    volatile double x = 0;
    for (int i = 0; i < 20000000; ++i) x = x + 1e-9 * i;
  });
  EXPECT_GT(freeform::helper_cpu_ms(), before);
}

// After a worker stalled inside a chunk (another process had its core), loops run on the caller
// alone for a while; forget_parallel_stalls() (a thread of our own that ran beside the pool has
// ended) gives the next loop the pool again. Without it, the precompute's factorization after the
// ordering ahead ran on one core.
TEST(ParallelFor, AStallIsForgottenWhenOurOwnThreadEnds) {
  if (freeform::parallel_workers() == 0) GTEST_SKIP() << "one hardware thread";
  using namespace std::chrono_literals;
  freeform::forget_parallel_stalls();
  const std::thread::id caller = std::this_thread::get_id();
  // A stall: the caller's chunk waits until a worker has taken the other one, which sleeps for
  // longer than the caller's own share (its wait for the worker) and than the pool's threshold.
  std::atomic<bool> worker_started{false};
  const auto begin = std::chrono::steady_clock::now();
  parallel_for(2, 1, [&](std::ptrdiff_t, std::ptrdiff_t) {
    if (std::this_thread::get_id() != caller) {
      worker_started = true;
      std::this_thread::sleep_for(20ms + 2 * (std::chrono::steady_clock::now() - begin));
      return;
    }
    for (int i = 0; i < 200 && !worker_started; ++i) std::this_thread::sleep_for(1ms);
  });
  if (!worker_started) GTEST_SKIP() << "no worker ran within 200 ms";
  EXPECT_EQ(threads_of_a_loop(), std::set<std::thread::id>{caller});  // backing off: the caller alone
  freeform::forget_parallel_stalls();
  EXPECT_GT(threads_of_a_loop().size(), 1u);
}

TEST(ParallelFor, HeldThreadsTakeTheWorkersSeats) {
  if (freeform::parallel_workers() == 0) GTEST_SKIP() << "one hardware thread";
  freeform::forget_parallel_stalls();
  auto held = hold_all_but_one();
  EXPECT_EQ(threads_of_a_loop(), std::set<std::thread::id>{std::this_thread::get_id()});  // the budget is spent
  held.clear();
  EXPECT_GT(threads_of_a_loop().size(), 1u);
}

TEST(RunTasks, ItsThreadsHoldTheirSeats) {
  const int budget = freeform::thread_budget();
  std::mutex m;
  std::set<std::thread::id> ids;
  int least_free = budget;
  const auto task = [&](int) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const std::lock_guard lock(m);
    ids.insert(std::this_thread::get_id());
    least_free = std::min(least_free, freeform::threads_free());
  };
  freeform::run_tasks(4 * budget, task);
  ASSERT_LE(static_cast<int>(ids.size()), budget);
  // Each thread it started held a seat, which the pool's loops meanwhile could not take.
  EXPECT_LE(least_free, std::max(1, budget - static_cast<int>(ids.size()) + 1));
  EXPECT_EQ(freeform::threads_free(), budget);  // all seats given back
  const auto held = hold_all_but_one();
  ids.clear();
  freeform::run_tasks(8, task);
  EXPECT_EQ(ids, std::set<std::thread::id>{std::this_thread::get_id()});
}

// Under an address-space limit a megabyte above the process's size (no room for a thread's 8 MB
// stack), the sum of 0 .. n - 1 by parallel_for; exits 0 if it is right.
[[noreturn]] void sum_with_no_room_for_a_thread() {
  std::ifstream statm("/proc/self/statm");
  std::size_t pages = 0;
  statm >> pages;
  const rlim_t size = pages * static_cast<rlim_t>(sysconf(_SC_PAGESIZE)) + (1 << 20);
  const rlimit limit{size, size};
  if (setrlimit(RLIMIT_AS, &limit) != 0) std::_Exit(2);
  constexpr long n = 100000;
  std::atomic<long> sum{0};
  parallel_for(n, 1, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (std::ptrdiff_t i = lo; i < hi; ++i) sum += static_cast<long>(i);
  });
  std::_Exit(sum == n * (n - 1) / 2 ? 0 : 1);
}

// A process whose address-space limit leaves no room for a thread's stack: the pool's first
// loop starts no worker and runs every index on the caller. Until 2026-12-07 the failed start
// escaped parallel_for as std::system_error and `freeform deform` aborted under `ulimit -v`
// (the hostile sweep's memory caps at 150 MB). In a fresh process (the pool is made once).
TEST(ParallelFor, NoThreadToBeHadRunsTheLoopOnTheCaller) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "ASan maps far more address space than a limit near the process's size allows";
#else
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(sum_with_no_room_for_a_thread(), ::testing::ExitedWithCode(0), "");
#endif
}
