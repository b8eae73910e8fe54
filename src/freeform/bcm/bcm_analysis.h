// The symbolic half of the BCM factorization, started ahead on a thread of its own. A_pp's
// pattern depends only on the connectivity, the free set and k, not on positions or smoothness,
// so CHOLMOD can order it (METIS: 15 s at 1M free, k = 3, single-threaded) while the operator
// shape, the anisotropic parametrization and the assembly run on the caller's thread.
#pragma once

#include "freeform/bcm/settings.h"
#include "freeform/mesh/mesh.h"
#include "freeform/numerics/sparse_solver.h"
#include "freeform/regions/regions.h"

#include <Eigen/SparseCore>

#include <atomic>
#include <functional>
#include <future>
#include <memory>

namespace freeform {

// The lower triangle of A_pp's pattern (values 0), rows and columns in assemble_bcm_system's
// free order: (i, j) for free vertices at most k edges apart (the walks of S_k = L W ... L).
// Once *stop is set (checked every few thousand columns) it returns an empty matrix.
Eigen::SparseMatrix<double> bcm_lower_pattern(const Mesh& mesh, const Regions& regions, int order,
                                              const std::atomic<bool>* stop = nullptr);

class BcmAnalysis {
 public:
  // Starts only where it can pay off: at least min_free free vertices, a solver setting that
  // allows CHOLMOD and a system expected to be symmetric (k <= 2, or every boundary
  // smoothness 0 or 2 at k = 3: docs/bcm.md), and where a core is left beside the caller's and
  // the analyses already running (threads_free() >= 2: never more threads than cores).
  // mesh and regions must outlive this.
  // before_ordering (tests): called on the thread between the pattern and the ordering.
  BcmAnalysis(const Mesh& mesh, const Regions& regions, const BcmSettings& settings, int min_free = kMinFree,
              std::function<void()> before_ordering = {});
  // Without get() (a cancel or an error unwinding) it waits only until the thread stops
  // reading mesh and regions (a few thousand pattern columns). An ordering already running
  // cannot be interrupted (CHOLMOD, METIS): it finishes on its own and is dropped, so a
  // cancelled editor precompute does not hold the next one for up to 20 s at 1M free.
  ~BcmAnalysis();
  BcmAnalysis(const BcmAnalysis&) = delete;
  BcmAnalysis& operator=(const BcmAnalysis&) = delete;

  bool started() const { return started_; }
  // Waits for the analysis; null if none was started or it failed (the solver then analyzes A).
  CholeskyAnalysis* get();
  double ms() const;      // the thread's time (pattern and analysis), after get()
  double cpu_ms() const;  // its CPU time, with the threads its ordering started

  // Multiresolution on the subdivided bunny, k = 3, precompute with / without: 35k free 1.3-1.4 /
  // 0.9-1.2 s (the thread competes with the operator shape), 140k 5.7-5.9 / 6.7-7.2 s, 300k
  // 13.6 / 17.0-17.3 s, 1M 45-49 / 58 s (docs/benchmarks.md, "Stop 34").
  static constexpr int kMinFree = 100000;

 private:
  struct Shared;  // what the thread shares with this object, which it may outlive
  std::shared_ptr<Shared> shared_;
  bool started_ = false;
  std::future<void> read_done_;  // the thread no longer reads mesh and regions
  std::future<std::unique_ptr<CholeskyAnalysis>> future_;
  std::unique_ptr<CholeskyAnalysis> result_;
};

}  // namespace freeform
