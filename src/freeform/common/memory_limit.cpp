#include "freeform/common/memory_limit.h"

#include "freeform/common/error.h"
#include "freeform/common/parallel.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

// Weak: resolved only when the BLAS linked in is OpenBLAS.
extern "C" int openblas_get_num_threads(void) __attribute__((weak));

namespace freeform {
namespace {

std::size_t virtual_size() {
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return 0;
  unsigned long pages = 0;
  const int n = std::fscanf(f, "%lu", &pages);
  std::fclose(f);
  return n == 1 ? pages * static_cast<std::size_t>(sysconf(_SC_PAGESIZE)) : 0;
}

std::string megabytes(std::size_t bytes) { return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB"; }

}  // namespace

std::optional<std::size_t> address_space_headroom() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return std::nullopt;
  const std::size_t used = virtual_size();
  return limit.rlim_cur > used ? static_cast<std::size_t>(limit.rlim_cur - used) : 0;
}

void throw_out_of_memory(const std::string& what, std::size_t bytes, std::size_t left) {
  throw OutOfMemory("out of memory while " + what + ": it needs about " + megabytes(bytes) +
                    ", the process may allocate " + megabytes(left) + " more (ulimit -v)");
}

std::string out_of_memory_message() {
  rlimit limit{};
  if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return "out of memory";
  return "out of memory: the process reached its address-space limit of " +
         megabytes(static_cast<std::size_t>(limit.rlim_cur)) + " (ulimit -v)";
}

std::size_t blas_buffer_bytes() {
  if (!openblas_get_num_threads) return 0;
  constexpr std::size_t kOpenBlasBuffer = std::size_t{128} << 20;
  // One buffer per OpenBLAS thread, and one per pool worker that calls it (the factorization's
  // subtrees, numerics/supernodal_factorization.h).
  return kOpenBlasBuffer * static_cast<std::size_t>(std::max(openblas_get_num_threads(), 1) + thread_budget() - 1);
}

}  // namespace freeform
