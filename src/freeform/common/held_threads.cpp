#include "freeform/common/held_threads.h"

#include "freeform/common/parallel.h"

#include <algorithm>
#include <atomic>

namespace freeform {
namespace {
std::atomic<int> held{0};
}

HeldThread::HeldThread() { ++held; }
HeldThread::~HeldThread() {
  --held;
  forget_parallel_stalls();
}

int threads_free() { return std::max(1, thread_budget() - held.load()); }

}  // namespace freeform
