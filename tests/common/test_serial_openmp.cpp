// SerialOpenMp (common/serial_openmp.h): inside the scope, a region asking for 4 threads runs
// with one; afterwards it gets its team again, and another thread keeps its teams meanwhile.
#include "freeform/common/serial_openmp.h"

#include <gtest/gtest.h>

#include <omp.h>

#include <thread>

namespace {

int team_of_four() {
  int size = 0;
#pragma omp parallel num_threads(4)
  {
#pragma omp single
    size = omp_get_num_threads();
  }
  return size;
}

}  // namespace

TEST(SerialOpenMp, OneThreadPerRegionInItsScopeOnly) {
  ASSERT_EQ(team_of_four(), 4) << "OMP_THREAD_LIMIT or OMP_DYNAMIC is set: nothing to compare with";
  const int levels = omp_get_max_active_levels();
  {
    const freeform::SerialOpenMp serial;
    EXPECT_EQ(team_of_four(), 1);
    int other = 0;
    std::thread([&] { other = team_of_four(); }).join();
    EXPECT_EQ(other, 4);
  }
  EXPECT_EQ(team_of_four(), 4);
  EXPECT_EQ(omp_get_max_active_levels(), levels);
}
