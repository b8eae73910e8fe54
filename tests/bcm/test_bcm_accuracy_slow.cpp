// Order 3 on 140k and 250k free vertices against the independent mixed-form reference
// (issue 13: within 1e-6 of the bounding-box diagonal; unrefined, the solve is off by 2e-4 at
// 140k). Label "slow": `ctest --preset slow` (minutes), not in the default suite.
#include "accuracy_scene.h"

namespace freeform::test {
namespace {

class SlowAccuracy : public ::testing::TestWithParam<int> {};

TEST_P(SlowAccuracy, OrderThreeMatchesTheMixedForm) {
  FREEFORM_REQUIRE_CGAL_MESHES();
  BcmSettings s;
  s.order = 3;
  const AccuracyResult r = accuracy_at(GetParam(), s);
  EXPECT_LT(r.error, 1e-6);
  EXPECT_TRUE(r.stats.refinement_converged);
  EXPECT_LT(r.stats.forward_error, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Sizes, SlowAccuracy, ::testing::Values(140000, 250000));

}  // namespace
}  // namespace freeform::test
