// Moves a fixed-point iteration x <- G(x) on along its step where it slides: where plain steps
// keep their direction and size for several iterations, the iteration is creeping along a
// soft mode toward a fixed point far away (hundreds of steps of about 1e-3 of the extent on the
// gallery's slow bends and twists, docs/nonlinear.md item 38), which Anderson acceleration does
// not shorten: its combinations grow the residual there and drop their history. The iterate is
// then moved `stretch` steps on instead of one; the stretch doubles after each move that the
// next plain step confirms (about the same size, nearly the same direction), up to a cap, and
// falls back after one it does not. A move is like a combined iterate: the caller confirms
// convergence with a plain step after it.
#pragma once

#include <Eigen/Core>

namespace freeform {

class DriftExtrapolation {
 public:
  DriftExtrapolation();
  // Forgets the steps seen (a new problem, or an image not of the last iterate).
  void reset();
  // at: the iterate G was evaluated at; image: G(at), a plain image. Overwrites image with the
  // iterate moved on along the step and returns true where the last plain steps slide; `move`
  // false (a step already within the tolerance) only records the step.
  bool next(const Eigen::Ref<const Eigen::VectorXd>& at, Eigen::Ref<Eigen::VectorXd> image, bool move = true);
  double stretch() const { return stretch_; }

 private:
  // The three steps swap their storage: after the first iterations next() allocates nothing.
  Eigen::VectorXd step_;        // this step (workspace)
  Eigen::VectorXd last_step_;   // the previous plain step, where has_last_
  Eigen::VectorXd moved_step_;  // the step the last move stretched, until the next plain step
  bool has_last_ = false;       // false after a move or a reset
  int sliding_ = 0;             // plain steps in a row that kept the one before's direction and size
  double stretch_;              // steps the next move goes on
  bool confirming_ = false;     // the next plain step confirms (or not) the last move
};

}  // namespace freeform
