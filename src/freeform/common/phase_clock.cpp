#include "freeform/common/phase_clock.h"

#include <chrono>
#include <ctime>

namespace freeform {
namespace {

double clock_ms(clockid_t id) {
  timespec t{};
  clock_gettime(id, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

double wall_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

PhaseClock::PhaseClock() : wall0_(wall_ms()), cpu0_(process_cpu_ms()) {}

PhaseTime PhaseClock::elapsed() const { return {wall_ms() - wall0_, process_cpu_ms() - cpu0_}; }

double PhaseClock::process_cpu_ms() { return clock_ms(CLOCK_PROCESS_CPUTIME_ID); }
double PhaseClock::thread_cpu_ms() { return clock_ms(CLOCK_THREAD_CPUTIME_ID); }

}  // namespace freeform
