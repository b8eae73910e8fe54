// The parallel sparse-row kernels of the assembly (numerics/csr.h) against plain serial
// references: the same pattern and the same bits, over many row blocks.
#include "freeform/numerics/csr.h"
#include "freeform/numerics/sparse_solver.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <stdexcept>

namespace freeform {
namespace {

// A rows x cols matrix with about `per_row` entries per row near the diagonal (and some far),
// every row sorted, some exact zeros.
Csr random_csr(int rows, int cols, int per_row, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> near(-40, 40);
  std::uniform_int_distribution<int> any(0, cols - 1);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  Csr m;
  m.rows = rows;
  m.cols = cols;
  for (int i = 0; i < rows; ++i) {
    std::set<int> row;
    for (int t = 0; t < per_row; ++t) {
      const int centre = static_cast<int>(static_cast<long>(i) * cols / rows);
      row.insert(t % 5 == 4 ? any(rng) : std::clamp(centre + near(rng), 0, cols - 1));
    }
    for (int c : row) {
      m.inner.push_back(c);
      m.value.push_back(c % 7 == 3 ? 0.0 : value(rng));
    }
    m.outer.push_back(static_cast<int>(m.inner.size()));
  }
  return m;
}

// The serial definition: each row's entries accumulated in the order of the loops.
Csr reference_product(const Csr& lhs, const Eigen::VectorXd& w, const Csr& rhs, int rows) {
  Csr out;
  out.rows = rows;
  out.cols = rhs.cols;
  for (int i = 0; i < rows; ++i) {
    std::vector<std::pair<int, double>> acc;  // in first-touch order
    for (int t = lhs.outer[i]; t < lhs.outer[i + 1]; ++t) {
      const int j = lhs.inner[t];
      if (j >= rhs.rows) continue;
      const double f = lhs.value[t] * w[j];
      for (int u = rhs.outer[j]; u < rhs.outer[j + 1]; ++u) {
        auto it = std::find_if(acc.begin(), acc.end(), [&](const auto& e) { return e.first == rhs.inner[u]; });
        if (it == acc.end()) it = acc.insert(acc.end(), {rhs.inner[u], 0.0});
        it->second += f * rhs.value[u];
      }
    }
    std::sort(acc.begin(), acc.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [c, v] : acc) {
      out.inner.push_back(c);
      out.value.push_back(v);
    }
    out.outer.push_back(static_cast<int>(out.inner.size()));
  }
  return out;
}

void expect_same(const Csr& a, const Csr& b) {
  ASSERT_EQ(a.rows, b.rows);
  ASSERT_EQ(a.cols, b.cols);
  ASSERT_EQ(a.outer, b.outer);
  ASSERT_TRUE(std::equal(a.inner.begin(), a.inner.end(), b.inner.begin(), b.inner.end()));
  for (std::size_t t = 0; t < a.value.size(); ++t) ASSERT_EQ(a.value[t], b.value[t]) << "entry " << t;  // bits
}

TEST(Csr, ProductHasTheSerialBitsOverManyBlocks) {
  const int n = 9 * detail::kCsrBlockRows + 123;  // ten blocks, the last one short
  const Csr lhs = random_csr(n, n + 500, 7, 1);
  const Csr rhs = random_csr(n, n + 900, 6, 2);  // lhs columns beyond rhs.rows are empty rows
  Eigen::VectorXd w = Eigen::VectorXd::Random(n + 500);
  w[17] = 0.0;  // a zero weight keeps its structural entries
  for (const int rows : {n, n - 5000, 1}) {
    SCOPED_TRACE(rows);
    const Csr got = scaled_product(lhs, w, rhs, rows);
    expect_same(got, reference_product(lhs, w, rhs, rows));
  }
}

TEST(Csr, ColumnBlockIsTheColumnMajorCopy) {
  const int n = 7 * detail::kCsrBlockRows + 77;
  const Csr x = random_csr(n, n + 3000, 9, 3);
  for (const auto& [c0, c1, drop] : {std::tuple{0, n + 3000, false}, std::tuple{0, n, false},
                                     std::tuple{n, n + 3000, true}, std::tuple{5, 6, true}}) {
    SCOPED_TRACE(testing::Message() << c0 << ".." << c1 << " drop " << drop);
    std::vector<Eigen::Triplet<double>> kept;
    for (int i = 0; i < n; ++i)
      for (int t = x.outer[i]; t < x.outer[i + 1]; ++t)
        if (x.inner[t] >= c0 && x.inner[t] < c1 && !(drop && x.value[t] == 0.0))
          kept.emplace_back(i, x.inner[t] - c0, -2.0 * x.value[t]);
    Eigen::SparseMatrix<double> want(n, c1 - c0);
    want.setFromTriplets(kept.begin(), kept.end());  // one entry per position: nothing summed
    const Eigen::SparseMatrix<double> got = column_block(x, c0, c1, -2.0, drop);
    ASSERT_EQ(got.nonZeros(), static_cast<Eigen::Index>(kept.size()));
    ASSERT_TRUE(got.isCompressed());
    for (Eigen::Index j = 0; j <= got.cols(); ++j) ASSERT_EQ(got.outerIndexPtr()[j], want.outerIndexPtr()[j]);
    for (Eigen::Index t = 0; t < got.nonZeros(); ++t) {
      ASSERT_EQ(got.innerIndexPtr()[t], want.innerIndexPtr()[t]);
      ASSERT_EQ(got.valuePtr()[t], want.valuePtr()[t]);
    }
  }
}

// A block's error (bad_alloc in a real run) comes back to the caller, not std::terminate.
TEST(Csr, BlockErrorsReachTheCaller) {
  const int n = 8 * detail::kCsrBlockRows;
  const auto fill = [](int begin, int end, CsrBlock& out) {
    if (begin == 5 * detail::kCsrBlockRows) throw std::runtime_error("block 5");
    out.row_end.assign(static_cast<std::size_t>(end - begin), 0);
  };
  EXPECT_THROW(build_csr(n, n, fill), std::runtime_error);
}

TEST(Csr, LargeSymmetryCheckFindsOneBadEntry) {
  const int n = 40000;
  std::vector<Eigen::Triplet<double>> t;
  std::mt19937 rng(4);
  std::uniform_int_distribution<int> offset(1, 60);
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.0);
    const int j = std::min(n - 1, i + offset(rng));
    if (j == i) continue;
    t.emplace_back(i, j, -0.5);
    t.emplace_back(j, i, -0.5);
  }
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  EXPECT_TRUE(is_symmetric(a));
  Eigen::SparseMatrix<double> b = a;
  b.coeffRef(n - 2, n - 1) += 1e-6;  // in the last columns, far from the first chunk
  EXPECT_FALSE(is_symmetric(b));
  EXPECT_TRUE(is_symmetric(b, 1e-5));
  Eigen::SparseMatrix<double> c = a;
  c.coeffRef(3, 30000) = 1.0;  // no mirror
  c.makeCompressed();
  EXPECT_FALSE(is_symmetric(c));
  c.coeffRef(30000, 3) = 1.0;
  EXPECT_TRUE(is_symmetric(c));
  c.coeffRef(20000, 20000) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(is_symmetric(c));
}

}  // namespace
}  // namespace freeform
