// Runs the OpenMP regions a library opens in this thread with one thread each, for a scope.
// Debian's CHOLMOD 5.12 opens a team of CHOLMOD_OMP_NUM_THREADS = 4 (fixed when it was built) for
// every supernode loop over 64-128 entries: about 730,000 team wake-ups in one factorization of a
// 1M-row Laplacian, on 2 cores next to OpenBLAS's own threads. Serial teams made the 1M-free
// k = 3 factorization 16.5 -> 11.8 s (docs/benchmarks.md, "Stop 34"); the BLAS stays parallel.
// max-active-levels is a per-thread setting (OpenMP 5.0, libgomp since GCC 11): other threads,
// such as a per-frame loop while the editor precomputes, keep their teams.
#pragma once

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace freeform {

class SerialOpenMp {
 public:
#if defined(_OPENMP)
  SerialOpenMp() : saved_(omp_get_max_active_levels()) { omp_set_max_active_levels(0); }
  ~SerialOpenMp() { omp_set_max_active_levels(saved_); }
#else
  SerialOpenMp() = default;
#endif
  SerialOpenMp(const SerialOpenMp&) = delete;
  SerialOpenMp& operator=(const SerialOpenMp&) = delete;

 private:
#if defined(_OPENMP)
  int saved_;
#endif
};

}  // namespace freeform
