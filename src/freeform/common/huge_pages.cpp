#include "freeform/common/huge_pages.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace freeform {

namespace {

bool opted_out() {
  static const bool out = [] {
    const char* v = std::getenv("FREEFORM_HUGE_PAGES");
    return v != nullptr && std::strcmp(v, "0") == 0;
  }();
  return out;
}

bool under_instrumentation() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return true;  // the sanitizer's allocator replaces glibc's: the tunable would change nothing
#else
  const char* preload = std::getenv("LD_PRELOAD");
  return preload != nullptr && std::strstr(preload, "valgrind") != nullptr;  // exec would leave valgrind
#endif
}

bool transparent_huge_pages_on_request() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(in, modes);
  return modes.find("[madvise]") != std::string::npos;
}

}  // namespace

void advise_huge_pages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (p == nullptr || bytes < kHugePageBytes || opted_out()) return;
  constexpr std::uintptr_t page = 4096;
  const auto begin = reinterpret_cast<std::uintptr_t>(p) & ~(page - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(p) + bytes + page - 1) & ~(page - 1);
  // A refusal (THP disabled, an old kernel) leaves ordinary pages: nothing to report.
  (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

void* malloc_huge(std::size_t bytes) {
  void* p = std::malloc(bytes);
  advise_huge_pages(p, bytes);
  return p;
}

void* calloc_huge(std::size_t count, std::size_t size) {
  void* p = std::calloc(count, size);
  if (p != nullptr) advise_huge_pages(p, count * size);  // calloc refused count * size overflowing
  return p;
}

void* realloc_huge(void* p, std::size_t bytes) {
  void* q = std::realloc(p, bytes);
  advise_huge_pages(q, bytes);
  return q;
}

void restart_with_huge_page_malloc(char** argv) {
#if defined(__linux__) && defined(__GLIBC__)
  if (argv == nullptr || std::getenv("GLIBC_TUNABLES") != nullptr || opted_out() || under_instrumentation() ||
      !transparent_huge_pages_on_request())
    return;
  if (setenv("GLIBC_TUNABLES", "glibc.malloc.hugetlb=1", 0) != 0) return;
  execv("/proc/self/exe", argv);
  unsetenv("GLIBC_TUNABLES");  // exec failed: go on as we are
#else
  (void)argv;
#endif
}

}  // namespace freeform
