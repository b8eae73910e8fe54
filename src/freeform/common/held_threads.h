// Threads that long work holds beside the caller's (the ordering ahead, bcm/bcm_analysis.h, and
// run_tasks' threads while they run). Work that could use every core asks threads_free() first
// (issue 43: never more threads than the budget): a parallel_for loop lets at most
// threads_free() - 1 pool workers join, run_tasks starts as many, and the numeric factorization
// runs its subtrees on the pool only where two threads are left, so on 2 cores beside the
// ordering, the longer of the two, it stays CHOLMOD's, with the BLAS on the core left.
#pragma once

namespace freeform {

// Holds one thread for its scope.
class HeldThread {
 public:
  HeldThread();
  ~HeldThread();
  HeldThread(const HeldThread&) = delete;
  HeldThread& operator=(const HeldThread&) = delete;
};

// thread_budget() less the threads held now, at least 1.
int threads_free();

}  // namespace freeform
