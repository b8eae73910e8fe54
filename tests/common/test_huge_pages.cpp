// common/huge_pages.h against what the kernel reports: the advised mapping's VmFlags in
// /proc/self/smaps, and the environment a restarted program sees.
#include "freeform/common/huge_pages.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace freeform {
namespace {

std::string thp_mode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(in, modes);
  return modes;
}

// The VmFlags line of the mapping that holds p, or "" if none does.
std::string vm_flags_of(const void* p) {
  std::ifstream in("/proc/self/smaps");
  const auto a = reinterpret_cast<std::uintptr_t>(p);
  bool inside = false;
  for (std::string line; std::getline(in, line);) {
    std::uintptr_t lo = 0, hi = 0;
    if (std::sscanf(line.c_str(), "%lx-%lx ", &lo, &hi) == 2 && line.find('-') < 17) {
      inside = lo <= a && a < hi;
    } else if (inside && line.rfind("VmFlags:", 0) == 0) {
      return line;
    }
  }
  return {};
}

bool has_flag(const std::string& flags, const char* flag) {
  std::istringstream words(flags);
  for (std::string w; words >> w;)
    if (w == flag) return true;
  return false;
}

TEST(HugePages, LargeBlocksAreAdvised) {
  if (thp_mode().find("[never]") != std::string::npos || thp_mode().empty())
    GTEST_SKIP() << "transparent huge pages are off on this machine";
  constexpr std::size_t big = 16 * kHugePageBytes;
  void* p = malloc_huge(big);
  ASSERT_NE(p, nullptr);
  EXPECT_TRUE(has_flag(vm_flags_of(p), "hg")) << vm_flags_of(p);
  std::free(p);
  // A small block grown past the threshold lands in a fresh mapping (mremap of an advised one
  // would keep its flag): only realloc_huge's own advice can mark it.
  void* q = realloc_huge(std::malloc(64), big);
  ASSERT_NE(q, nullptr);
  EXPECT_TRUE(has_flag(vm_flags_of(q), "hg")) << vm_flags_of(q);
  std::free(q);
}

TEST(HugePages, AllocatorsKeepMallocSemantics) {
  constexpr std::size_t n = 3 * kHugePageBytes / sizeof(double);
  auto* z = static_cast<double*>(calloc_huge(n, sizeof(double)));
  ASSERT_NE(z, nullptr);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; i += 997) sum += z[i];
  EXPECT_EQ(sum, 0.0);
  for (std::size_t i = 0; i < n; ++i) z[i] = static_cast<double>(i);
  auto* grown = static_cast<double*>(realloc_huge(z, 2 * n * sizeof(double)));
  ASSERT_NE(grown, nullptr);
  EXPECT_EQ(grown[0], 0.0);
  EXPECT_EQ(grown[n - 1], static_cast<double>(n - 1));
  auto* small = static_cast<char*>(malloc_huge(16));
  ASSERT_NE(small, nullptr);
  std::strcpy(small, "fifteen chars..");
  EXPECT_STREQ(small, "fifteen chars..");
  std::free(small);
  std::free(grown);
}

// The probe restarts itself and prints GLIBC_TUNABLES and its arguments.
std::string probe(const std::string& env) {
  const std::string cmd = env + " " + FREEFORM_HUGE_PAGES_PROBE + " one 'two words'";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return "(popen failed)";
  std::array<char, 512> buffer{};
  std::string out;
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) out += buffer.data();
  pclose(pipe);
  return out;
}

bool sanitized() {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  return true;
#else
  return false;
#endif
}

TEST(HugePages, RestartSetsTheMallocTunableOnceAndKeepsTheArguments) {
  const bool expected = thp_mode().find("[madvise]") != std::string::npos && !sanitized();
  EXPECT_EQ(probe("env -u GLIBC_TUNABLES -u FREEFORM_HUGE_PAGES"),
            std::string(expected ? "glibc.malloc.hugetlb=1" : "(unset)") + "|one|two words\n");
}

TEST(HugePages, RestartRespectsTheUsersChoice) {
  EXPECT_EQ(probe("env -u GLIBC_TUNABLES FREEFORM_HUGE_PAGES=0"), "(unset)|one|two words\n");
  EXPECT_EQ(probe("env -u FREEFORM_HUGE_PAGES GLIBC_TUNABLES=glibc.malloc.check=0"),
            "glibc.malloc.check=0|one|two words\n");
}

}  // namespace
}  // namespace freeform
