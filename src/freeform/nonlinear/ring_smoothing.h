// The rotation fit's low-pass filter over the vertices' covariances: n passes that each add a
// vertex's neighbours to it, (I + A)^n C with A the graph's adjacency. The kernel's width grows
// only as sqrt(n). From 16 passes on, a Chebyshev polynomial of degree about 2.4 sqrt(n) in
// I + A with the same width replaces the power, at a pass's cost per degree
// (docs/nonlinear.md, "The width of the rotation fit").
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <vector>

namespace freeform {

// The connected components of the graph below (the rows of lap, each adjacent to its
// off-diagonal columns that are rows too): per row its component, numbered in the order of
// their first rows; `count` gets their number.
std::vector<int> connected_rows(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int& count);

class RingSmoothing {
 public:
  // The graph: the rows of lap, each adjacent to its off-diagonal columns that are rows too.
  RingSmoothing(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int passes);
  // Each connected component with its own passes: passes[c] for component c of connected_rows()
  // (each is smoothed as if alone), or one count for all. Throws InternalError on another size.
  RingSmoothing(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, const std::vector<int>& passes);

  // Smooths cov (one matrix per row of lap) in place with `work` (resized) as scratch. Each vertex's result
  // has an arbitrary positive scale (the rotation fit does not see it).
  void apply(std::vector<Eigen::Matrix3d>& cov, std::vector<Eigen::Matrix3d>& work) const;

  // Neighbour sums per apply(), the most of any component: its passes, or its Chebyshev
  // polynomial's degree.
  int sums() const;

 private:
  // Chooses each component's Chebyshev filter (degree_, centre_, half_) from 16 passes on, or
  // leaves its power.
  void design_filters();
  // y_i plus y of i's neighbours.
  template <class T>
  T sum_at(const std::vector<T>& y, std::size_t i) const {
    T s = y[i];
    for (int k = offset_[i]; k < offset_[i + 1]; ++k)
      s += y[static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)])];
    return s;
  }

  std::vector<int> offset_, nbr_;  // CSR
  int n_ = 0;
  std::vector<int> component_;              // per vertex
  std::vector<int> passes_, degree_;        // per component; degree_ > 0: the Chebyshev filter's degree
  std::vector<std::vector<double>> roots_;  // per component: cos(theta) of each factor, in apply()'s order
  // Per vertex, of its connected component: the filter's variable is (lambda - centre) / half.
  std::vector<double> centre_, half_;
};

}  // namespace freeform
