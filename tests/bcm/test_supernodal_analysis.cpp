// numerics/supernodal_analysis.h against cholmod_analyze_p with CHOLMOD_GIVEN on BCM's own
// k = 1..3 patterns: the same symbolic factor, every array bit for bit, for the orderings the
// solver hands it (nested dissection) and for arbitrary ones; bad input refused like CHOLMOD.
#include "bcm_fixtures.h"

#if FREEFORM_TEST_HAVE_CHOLMOD
#include "freeform/bcm/bcm_analysis.h"
#include "freeform/mesh/generators.h"
#include "freeform/numerics/nested_dissection.h"
#include "freeform/numerics/supernodal_analysis.h"

#include <Eigen/CholmodSupport>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace freeform::test {
namespace {

struct Common {
  cholmod_common c{};
  Common() {
    cholmod_start(&c);
    c.print = 0;
    c.supernodal = CHOLMOD_SUPERNODAL;
    c.nmethods = 1;
    c.method[0].ordering = CHOLMOD_GIVEN;
  }
  ~Common() { cholmod_finish(&c); }
};

struct Factor {
  Common common;
  cholmod_factor* l = nullptr;
  ~Factor() { cholmod_free_factor(&l, &common.c); }
};

Eigen::SparseMatrix<double> bcm_pattern(int cells, int order) {
  const Mesh plane = Mesh::from_soup(make_bumpy_plane(cells, cells, 0.05, 2.0));
  std::vector<Vertex> support;
  for (Vertex v : plane.vertices())
    if (plane.position(v).x() > 0.05) support.push_back(v);
  const Regions regions(plane, support, {{within(plane, Vec3(0.9, 0.5, 0), 0.05), true}});
  Eigen::SparseMatrix<double> lower = bcm_lower_pattern(plane, regions, order);
  lower.makeCompressed();
  return lower;
}

cholmod_sparse view(const Eigen::SparseMatrix<double>& lower) {
  return Eigen::viewAsCholmod(lower.selfadjointView<Eigen::Lower>());
}

std::vector<int> ints(const void* p, std::size_t n) {
  const int* a = static_cast<const int*>(p);
  return std::vector<int>(a, a + n);
}

void expect_same_factor(const cholmod_factor& got, const cholmod_factor& want) {
  ASSERT_EQ(got.n, want.n);
  EXPECT_EQ(got.is_super, want.is_super);
  EXPECT_EQ(got.ordering, want.ordering);
  EXPECT_EQ(ints(got.Perm, got.n), ints(want.Perm, want.n));
  EXPECT_EQ(ints(got.ColCount, got.n), ints(want.ColCount, want.n));
  ASSERT_EQ(got.nsuper, want.nsuper);
  EXPECT_EQ(got.ssize, want.ssize);
  EXPECT_EQ(got.xsize, want.xsize);
  EXPECT_EQ(got.maxcsize, want.maxcsize);
  EXPECT_EQ(got.maxesize, want.maxesize);
  EXPECT_EQ(ints(got.super, got.nsuper + 1), ints(want.super, want.nsuper + 1));
  EXPECT_EQ(ints(got.pi, got.nsuper + 1), ints(want.pi, want.nsuper + 1));
  EXPECT_EQ(ints(got.px, got.nsuper + 1), ints(want.px, want.nsuper + 1));
  EXPECT_EQ(ints(got.s, got.ssize), ints(want.s, want.ssize));
}

void expect_like_cholmod(const Eigen::SparseMatrix<double>& lower, std::vector<int> perm, bool postorder = true) {
  cholmod_sparse a = view(lower);
  Factor want, got;
  want.common.c.postorder = got.common.c.postorder = postorder;
  want.l = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &want.common.c);
  ASSERT_NE(want.l, nullptr);
  got.l = analyze_supernodal_given(a, perm.data(), &got.common.c);
  ASSERT_NE(got.l, nullptr) << "status " << got.common.c.status;
  EXPECT_EQ(got.common.c.status, want.common.c.status);
  EXPECT_EQ(got.common.c.lnz, want.common.c.lnz);
  EXPECT_EQ(got.common.c.fl, want.common.c.fl);
  expect_same_factor(*got.l, *want.l);
}

TEST(SupernodalAnalysis, SameSymbolicFactorAsCholmodForNestedDissection) {
  for (int order : {1, 2, 3}) {
    SCOPED_TRACE("order " + std::to_string(order));
    const Eigen::SparseMatrix<double> lower = bcm_pattern(70, order);
    for (int parts : {1, 4}) expect_like_cholmod(lower, nested_dissection(lower, parts));
  }
}

TEST(SupernodalAnalysis, SameSymbolicFactorForAnyOrdering) {
  const Eigen::SparseMatrix<double> lower = bcm_pattern(30, 2);
  std::vector<int> perm(static_cast<std::size_t>(lower.rows()));
  std::iota(perm.begin(), perm.end(), 0);
  expect_like_cholmod(lower, perm);
  std::reverse(perm.begin(), perm.end());
  expect_like_cholmod(lower, perm);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(7));
  expect_like_cholmod(lower, perm);
  expect_like_cholmod(lower, perm, false);  // no weighted postorder: the given ordering as it is
}

TEST(SupernodalAnalysis, RefusesWhatCholmodRefuses) {
  const Eigen::SparseMatrix<double> lower = bcm_pattern(8, 2);
  cholmod_sparse a = view(lower);
  std::vector<int> perm(static_cast<std::size_t>(lower.rows()));
  std::iota(perm.begin(), perm.end(), 0);
  perm[3] = perm[4];  // not a permutation
  Factor got;
  got.l = analyze_supernodal_given(a, perm.data(), &got.common.c);
  EXPECT_EQ(got.l, nullptr);
  EXPECT_EQ(got.common.c.status, CHOLMOD_INVALID);
  perm[3] = static_cast<int>(lower.rows());  // out of range
  got.l = analyze_supernodal_given(a, perm.data(), &got.common.c);
  EXPECT_EQ(got.l, nullptr);
  EXPECT_EQ(got.common.c.status, CHOLMOD_INVALID);
}

}  // namespace
}  // namespace freeform::test
#endif
