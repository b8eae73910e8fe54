// Prints GLIBC_TUNABLES and its arguments after restart_with_huge_page_malloc (test_huge_pages).
#include "freeform/common/huge_pages.h"

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  freeform::restart_with_huge_page_malloc(argv);
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  std::printf("%s", tunables != nullptr ? tunables : "(unset)");
  for (int i = 1; i < argc; ++i) std::printf("|%s", argv[i]);
  std::printf("\n");
  return 0;
}
