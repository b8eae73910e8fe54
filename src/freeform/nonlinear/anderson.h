// Anderson acceleration of a fixed-point iteration x <- G(x) (Walker & Ni 2011; Peng et al.,
// "Anderson Acceleration for Geometry Optimization and Physics Simulation", SIGGRAPH 2018).
// The nonlinear model's local/global alternation is such a G; plain iteration converges
// linearly and slowly on large supports (docs/nonlinear.md). The next iterate combines the
// last m images so that the combined residual G(x) - x is least-squares smallest. Safeguard:
// when the residual grows, the history is dropped and the plain image taken. Like any secant
// method it also finds fixed points that plain iteration would leave (unstable ones): the
// caller confirms convergence with a plain step.
#pragma once

#include <Eigen/Core>

namespace freeform {

class AndersonAcceleration {
 public:
  // dim: length of x; m: images combined (0: plain iteration).
  AndersonAcceleration(Eigen::Index dim, int m);

  // Forgets the history (a new problem, or an image not of the last iterate).
  void reset();
  // x: the iterate G was evaluated at; g: G(x). Records them and overwrites g with the next
  // iterate, the combination of the images (unless `combine` is false: then g stays the plain
  // image, e.g. to confirm convergence). Returns true when it combined images.
  bool next(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g, bool combine = true);

 private:
  int m_;
  int count_ = 0, newest_ = -1;  // columns in use, ring-buffer position of the newest
  bool has_last_ = false;
  Eigen::MatrixXd dg_, df_;          // dim x m: differences of successive images / residuals
  Eigen::VectorXd last_g_, last_f_;  // the previous image and residual
  Eigen::VectorXd f_;                // workspace: this residual
};

}  // namespace freeform
