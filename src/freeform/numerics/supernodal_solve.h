// Solves with a supernodal Cholesky factor on several cores (issue 43). CHOLMOD's own solve walks
// the supernodes one after the other, and the precompute solves with the whole factor once for
// the basis and once per refinement step. The same triangular solves here run the subtrees of the
// supernodal elimination tree concurrently, then the top of the tree (the last separators) in
// order, each of those by panels of columns whose rows below are split among the threads. The
// subtrees and row blocks depend on the tree alone, and their sums are added in a fixed order,
// so the result has the same bits on any number of threads.
#pragma once

#include <Eigen/Core>

#include <atomic>
#include <cstddef>
#include <optional>
#include <vector>

namespace freeform {

namespace detail {
struct SupernodalSweep;  // the right-hand sides being solved (supernodal_solve.cpp)
}

// A supernodal LL' factor of P A P' in CHOLMOD's layout (cholmod_factor with is_super, int
// indices, real values), borrowed: supernode s holds columns [super[s], super[s+1]); its rows are
// s_rows[pi[s] .. pi[s+1]) (the supernode's own columns first, then ascending) and its values
// the column-major block at x + px[s]. perm[k]: the row of A eliminated k-th (null: identity).
struct SupernodalFactor {
  int n = 0;
  int nsuper = 0;
  const int* super = nullptr;
  const int* pi = nullptr;
  const int* px = nullptr;
  const int* s_rows = nullptr;
  const double* x = nullptr;
  const int* perm = nullptr;
};

class SupernodalSolve {
 public:
  struct Subtree {
    int first = 0, last = 0;  // supernodes [first, last]; last is the root
    int col_end = 0;          // one past the last column
    int max_rows = 0;         // largest supernode's row count
  };

  // The schedule for `factor`'s tree; ok() is false where the layout is not the one above
  // (unsorted rows, subtrees not numbered contiguously), and the caller then solves otherwise.
  explicit SupernodalSolve(const SupernodalFactor& factor);
  bool ok() const { return ok_; }
  int subtrees() const { return static_cast<int>(subtrees_.size()); }
  const Subtree& subtree(int i) const { return subtrees_[static_cast<std::size_t>(i)]; }  // largest first
  const std::vector<int>& top_supernodes() const { return top_; }  // above every subtree, ascending
  // The factor's share that one thread solves alone: the supernodes above the subtrees, of the
  // large ones the triangles of their panels.
  double serial_share() const { return serial_share_; }

  // X = A^-1 B with the factor the schedule was made for (B: n by m); nullopt if a supernode's
  // rows are not within its subtree root's (a structure CHOLMOD does not make). The dense kernels
  // are AVX2 + FMA ones where the CPU has them, unless wide_kernels is false (for tests).
  std::optional<Eigen::MatrixXd> solve(const SupernodalFactor& factor, const Eigen::MatrixXd& b,
                                       bool wide_kernels = true) const;

 private:
  void forward_subtree(const SupernodalFactor& f, const Subtree& t, const detail::SupernodalSweep& w, double* work,
                       double* above, std::atomic<bool>& missing) const;
  void backward_subtree(const SupernodalFactor& f, const Subtree& t, const detail::SupernodalSweep& w,
                        double* work) const;

  bool ok_ = false;
  std::vector<Subtree> subtrees_;  // largest first
  std::vector<int> top_;           // supernodes above every subtree, ascending
  int top_max_rows_ = 0;
  double serial_share_ = 0.0;
};

}  // namespace freeform
