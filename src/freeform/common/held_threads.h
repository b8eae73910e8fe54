// Threads that long work holds beside the caller's (the ordering ahead, bcm/bcm_analysis.h), so
// that work which could use every core starts with the ones left instead (issue 43: the pool,
// the BLAS and the ordering never run more threads than cores). On 2 cores the factorization
// beside the ordering then stays on one thread, as the ordering is the longer of the two.
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
