// numerics/nested_dissection.h on BCM's own k = 3 pattern (bcm_lower_pattern): the ordering is
// a permutation and its Cholesky fill stays within 5 % of METIS's ordering of the whole graph
// (issue 43's bound), for 2 to 16 concurrently ordered parts. Not the same permutation on
// every call: METIS draws from the C library's rand(), one stream for all threads, so
// concurrent parts interleave their draws (docs/benchmarks.md, "Precompute on all cores").
#include "bcm_fixtures.h"

#include "freeform/bcm/bcm_analysis.h"
#include "freeform/mesh/generators.h"
#include "freeform/numerics/nested_dissection.h"

#include <algorithm>
#include <numeric>

namespace freeform::test {
namespace {

Eigen::SparseMatrix<double> plane_pattern(int cells, int order) {
  const Mesh plane = Mesh::from_soup(make_plane(cells, cells));
  std::vector<Vertex> support;
  for (Vertex v : plane.vertices())
    if (plane.position(v).x() > 0.05) support.push_back(v);
  const Regions regions(plane, support, {{within(plane, Vec3(0.9, 0.5, 0), 0.05), true}});
  return bcm_lower_pattern(plane, regions, order);
}

TEST(NestedDissection, PartsOrderedConcurrentlyFillLikeMetisOnTheWholeGraph) {
  const Eigen::SparseMatrix<double> lower = plane_pattern(150, 3);
  ASSERT_GT(lower.rows(), 20000);
  const double metis = cholesky_fill(lower, {});
  ASSERT_GT(metis, 0.0);
  for (int parts : {2, 4, 16}) {
    SCOPED_TRACE(std::to_string(parts) + " parts");
    const std::vector<int> perm = nested_dissection(lower, parts);
    ASSERT_EQ(perm.size(), static_cast<std::size_t>(lower.rows()));
    std::vector<int> sorted = perm;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> identity(perm.size());
    std::iota(identity.begin(), identity.end(), 0);
    EXPECT_EQ(sorted, identity);
    const double fill = cholesky_fill(lower, perm);
    EXPECT_LT(fill, 1.05 * metis) << fill << " against " << metis;
    // A fill-reducing ordering at all: the natural (breadth-first) order fills far more.
    EXPECT_LT(fill, 0.5 * cholesky_fill(lower, identity));
  }
}

TEST(NestedDissection, SmallGraphsAreOrderedWhole) {
  const Eigen::SparseMatrix<double> lower = plane_pattern(12, 2);
  const std::vector<int> perm = nested_dissection(lower, 8);
  ASSERT_EQ(perm.size(), static_cast<std::size_t>(lower.rows()));
  EXPECT_NEAR(cholesky_fill(lower, perm), cholesky_fill(lower, {}), 0.05 * cholesky_fill(lower, {}));
}

TEST(NestedDissection, PartsArePowersOfTwoCoveringTheThreads) {
  EXPECT_EQ(dissection_parts(1), 1);
  EXPECT_EQ(dissection_parts(2), 2);
  EXPECT_EQ(dissection_parts(3), 4);
  EXPECT_EQ(dissection_parts(16), 16);
  EXPECT_EQ(dissection_parts(1000), 64);
}

}  // namespace
}  // namespace freeform::test
