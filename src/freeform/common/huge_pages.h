// Large buffers on transparent huge pages where the kernel grants them on request (THP mode
// "madvise", Debian's and Ubuntu's default): their first touch costs one page fault per 2 MB
// instead of one per 4 KB, and the TLB covers them. At a million free vertices this cut the BCM
// precompute from 86-91 s to 50-52 s (docs/benchmarks.md, "Scale").
#pragma once

#include <cstddef>

namespace freeform {

// Blocks at least this large are advised.
constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

// Asks for huge pages over the pages [p, p + bytes) touches if bytes >= kHugePageBytes. Call it
// before the memory is first written; a no-op where the kernel or platform has no such request,
// and when the environment has FREEFORM_HUGE_PAGES=0 (this and restart_with_huge_page_malloc).
void advise_huge_pages(void* p, std::size_t bytes);

// std::malloc / calloc / realloc that advise huge pages for large blocks (release with std::free).
void* malloc_huge(std::size_t bytes);
void* calloc_huge(std::size_t count, std::size_t size);
void* realloc_huge(void* p, std::size_t bytes);

// glibc's malloc advises huge pages for all its large blocks (Eigen's, METIS's, ours) only when
// told at start-up, by GLIBC_TUNABLES=glibc.malloc.hugetlb=1. For a program's main(): if the
// kernel grants huge pages on request only (THP "madvise") and GLIBC_TUNABLES is unset, re-executes
// /proc/self/exe with it set (same process id, arguments and environment otherwise). Returns
// (does nothing) where that does not apply or fails, under sanitizers or valgrind, or when
// FREEFORM_HUGE_PAGES=0.
void restart_with_huge_page_malloc(char** argv);

}  // namespace freeform
