// Progress reporting and cooperative cancellation of long precomputations (the editor runs
// them on a background thread). A default Progress does nothing and never cancels.
#pragma once

#include "freeform/common/error.h"

#include <atomic>
#include <functional>
#include <string_view>

namespace freeform {

// Thrown at a checkpoint once cancellation was requested; never the user's data's fault.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

struct Progress {
  // Called from the computing thread: stage name ("assembly", "factorization", "basis",
  // "refinement", "detail"; "nonlinear": iterations / cap of one solve of that model) and
  // the fraction done in [0, 1].
  std::function<void(std::string_view stage, double fraction)> report;
  const std::atomic<bool>* cancel = nullptr;  // set to true to stop at the next checkpoint

  // Reports (if a callback is set), then throws Cancelled if cancellation was requested.
  void step(std::string_view stage, double fraction) const {
    if (report) report(stage, fraction);
    check();
  }
  void check() const {
    if (cancel && cancel->load(std::memory_order_relaxed)) throw Cancelled();
  }
};

}  // namespace freeform
