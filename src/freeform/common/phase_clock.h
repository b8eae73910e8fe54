// Wall and CPU time of a precompute phase. CPU time is the whole process's: a phase that keeps
// c cores busy shows cpu / wall near c, a serial one near 1, whatever the machine (issue 43).
// A phase that overlaps work on another thread (the ordering ahead, bcm/bcm_analysis.h) counts
// that thread's CPU time too.
#pragma once

#include <string>

namespace freeform {

struct PhaseTime {
  double wall_ms = 0;
  double cpu_ms = 0;
  PhaseTime& operator+=(const PhaseTime& o) {
    wall_ms += o.wall_ms;
    cpu_ms += o.cpu_ms;
    return *this;
  }
  PhaseTime operator-(const PhaseTime& o) const { return {wall_ms - o.wall_ms, cpu_ms - o.cpu_ms}; }
};

struct Phase {
  std::string name;
  PhaseTime time;
};

// Starts at construction.
class PhaseClock {
 public:
  PhaseClock();
  PhaseTime elapsed() const;
  static double process_cpu_ms();
  static double thread_cpu_ms();  // the calling thread's

 private:
  double wall0_, cpu0_;
};

}  // namespace freeform
