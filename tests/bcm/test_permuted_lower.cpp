// numerics/permuted_lower.h against P A P' built by Eigen from triplets: the same pattern, rows
// sorted in every column, and the same values, bit for bit; lower and upper triangles.
#include "freeform/numerics/permuted_lower.h"

#include <gtest/gtest.h>

#include <Eigen/Sparse>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace freeform {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// A symmetric n x n matrix with a banded part, random far entries, one dense row and column
// (longer than the insertion sort's columns) and some exact zeros.
SpMat random_symmetric(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> any(0, n - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  const auto add = [&](int i, int j, double v) {
    t.emplace_back(i, j, v);
    if (i != j) t.emplace_back(j, i, v);
  };
  for (int i = 0; i < n; ++i) {
    add(i, i, 4.0 + value(rng));
    for (int d = 1; d <= 6; ++d)
      if (i + d < n) add(i + d, i, d == 5 ? 0.0 : value(rng));
    if (i % 3 == 0) {
      const int j = any(rng);
      add(std::max(i, j), std::min(i, j), value(rng));
    }
  }
  for (int i = 200; i < n; i += std::max(1, n / 300)) add(i, 7, value(rng));
  SpMat a(n, n);
  a.setFromTriplets(t.begin(), t.end(), [](double, double b) { return b; });
  a.makeCompressed();
  return a;
}

std::vector<int> random_permutation(int n, unsigned seed) {
  std::vector<int> perm(static_cast<std::size_t>(n));
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(seed));
  return perm;
}

// tril(P A P') with (P A P')(a, b) = A(perm[a], perm[b]), by Eigen's own sorted assembly.
SpMat reference(const SpMat& full, const std::vector<int>& perm) {
  std::vector<int> inverse(perm.size());
  for (std::size_t k = 0; k < perm.size(); ++k) inverse[static_cast<std::size_t>(perm[k])] = static_cast<int>(k);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < full.outerSize(); ++j)
    for (SpMat::InnerIterator it(full, j); it; ++it) {
      const int a = inverse[static_cast<std::size_t>(it.row())], b = inverse[static_cast<std::size_t>(j)];
      if (a >= b) t.emplace_back(a, b, it.value());
    }
  SpMat r(full.rows(), full.cols());
  r.setFromTriplets(t.begin(), t.end());
  r.makeCompressed();
  return r;
}

void expect_same(const TriangleCsc& got, const SpMat& want) {
  ASSERT_EQ(got.outer.size(), static_cast<std::size_t>(want.cols()) + 1);
  ASSERT_TRUE(std::equal(got.outer.begin(), got.outer.end(), want.outerIndexPtr()));
  ASSERT_EQ(got.inner.size(), static_cast<std::size_t>(want.nonZeros()));
  EXPECT_TRUE(std::equal(got.inner.begin(), got.inner.end(), want.innerIndexPtr()));
  EXPECT_TRUE(std::equal(got.value.begin(), got.value.end(), want.valuePtr()));  // copies: exact
}

TEST(PermutedLower, IsEigensLowerTriangleOfThePermutedMatrixOverManyChunks) {
  for (int n : {1, 17, 30000}) {
    SCOPED_TRACE(n);
    const SpMat full = random_symmetric(n, 5u + static_cast<unsigned>(n));
    const SpMat lower = full.triangularView<Eigen::Lower>();
    const std::vector<int> perm = random_permutation(n, 9u);
    const TriangleCsc got =
        permuted_lower(n, lower.outerIndexPtr(), lower.innerIndexPtr(), lower.valuePtr(), perm.data());
    expect_same(got, reference(full, perm));
  }
}

// The symbolic analysis's copies: the upper triangle, and the pattern alone.
TEST(PermutedLower, UpperTriangleIsTheTransposeAndPatternsHaveNoValues) {
  const int n = 20000;
  const SpMat full = random_symmetric(n, 21u);
  const SpMat lower = full.triangularView<Eigen::Lower>();
  const std::vector<int> perm = random_permutation(n, 4u);
  const SpMat upper = reference(full, perm).transpose();
  expect_same(permuted_triangle(n, lower.outerIndexPtr(), lower.innerIndexPtr(), lower.valuePtr(), perm.data(),
                                Triangle::upper),
              upper);
  const TriangleCsc pattern =
      permuted_triangle(n, lower.outerIndexPtr(), lower.innerIndexPtr(), nullptr, perm.data(), Triangle::upper);
  EXPECT_TRUE(pattern.value.empty());
  EXPECT_TRUE(std::equal(pattern.inner.begin(), pattern.inner.end(), upper.innerIndexPtr(),
                         upper.innerIndexPtr() + upper.nonZeros()));
  EXPECT_TRUE(std::equal(pattern.outer.begin(), pattern.outer.end(), upper.outerIndexPtr()));
}

TEST(PermutedLower, IgnoresTheUpperTriangleAndKeepsTheIdentityOrder) {
  const int n = 5000;
  const SpMat full = random_symmetric(n, 3u);
  std::vector<int> identity(static_cast<std::size_t>(n));
  std::iota(identity.begin(), identity.end(), 0);
  // The whole matrix given: its upper triangle must not count twice.
  const TriangleCsc got =
      permuted_lower(n, full.outerIndexPtr(), full.innerIndexPtr(), full.valuePtr(), identity.data());
  const SpMat lower = full.triangularView<Eigen::Lower>();
  expect_same(got, lower);
}

}  // namespace
}  // namespace freeform
