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

class RingSmoothing {
 public:
  // The graph: the rows of lap, each adjacent to its off-diagonal columns that are rows too.
  RingSmoothing(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int passes);

  // Smooths cov (one matrix per row of lap) in place with `work` (resized) as scratch. Each vertex's result
  // has an arbitrary positive scale (the rotation fit does not see it).
  void apply(std::vector<Eigen::Matrix3d>& cov, std::vector<Eigen::Matrix3d>& work) const;

  // Neighbour sums per apply(): the passes, or the Chebyshev polynomial's degree.
  int sums() const { return degree_ > 0 ? degree_ : passes_; }

 private:
  // The component of each vertex, numbered 0 .. count - 1.
  std::vector<int> components(int& count) const;
  // Chooses the Chebyshev filter (degree_, centre_, half_), or leaves the power.
  void design_filter();
  // y_i plus y of i's neighbours.
  template <class T>
  T sum_at(const std::vector<T>& y, std::size_t i) const {
    T s = y[i];
    for (int k = offset_[i]; k < offset_[i + 1]; ++k)
      s += y[static_cast<std::size_t>(nbr_[static_cast<std::size_t>(k)])];
    return s;
  }

  std::vector<int> offset_, nbr_;  // CSR
  int n_ = 0, passes_ = 0;
  int degree_ = 0;  // > 0: the Chebyshev filter's degree
  // Per vertex, of its connected component: the filter's variable is (lambda - centre) / half.
  std::vector<double> centre_, half_;
};

}  // namespace freeform
