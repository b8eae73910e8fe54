#include "freeform/nonlinear/drift.h"

#include <algorithm>

namespace freeform {
namespace {
// A step slides on from the one before when the two are this parallel and its size is within
// this ratio of the other's; after this many such steps in a row the iterate is moved on. Chosen
// on the gallery's quick loop (docs/nonlinear.md item 38): the camel's head bent 114° slides at
// cosines of 0.9990-0.9999 and ratios of 1.001-1.01; steps that shrink (a converging iteration)
// or turn are left alone.
constexpr double kSlidingCosine = 0.995, kMinSlidingRatio = 0.9, kMaxSlidingRatio = 1.2;
constexpr int kSlidingSteps = 3;
// The first move's stretch (in steps), and its cap: the slides of the gallery's slow cases are
// hundreds of steps long and bend slowly.
constexpr double kStretch = 8.0, kMaxStretch = 64.0;
// A move is confirmed when the next plain step is at most this much larger than the stretched
// one and this parallel to it (slides bend: the step after a move of 8 turned by cosines of
// 0.74-0.99 on the camel, without growing).
constexpr double kConfirmRatio = 1.5, kConfirmCosine = 0.7;

double cosine(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const double n = a.norm() * b.norm();
  return n > 0.0 ? a.dot(b) / n : 0.0;
}
}  // namespace

DriftExtrapolation::DriftExtrapolation() : stretch_(kStretch) {}

void DriftExtrapolation::reset() {
  has_last_ = false;
  sliding_ = 0;
  stretch_ = kStretch;
  confirming_ = false;
}

bool DriftExtrapolation::next(const Eigen::Ref<const Eigen::VectorXd>& at, Eigen::Ref<Eigen::VectorXd> image,
                              bool move) {
  step_ = image - at;
  if (confirming_) {
    confirming_ = false;
    const bool confirmed =
        step_.norm() < kConfirmRatio * moved_step_.norm() && cosine(step_, moved_step_) > kConfirmCosine;
    stretch_ = confirmed ? std::min(2.0 * stretch_, kMaxStretch) : kStretch;
  }
  const bool slides = has_last_ && last_step_.size() == step_.size() && cosine(step_, last_step_) > kSlidingCosine &&
                      step_.norm() > kMinSlidingRatio * last_step_.norm() &&
                      step_.norm() < kMaxSlidingRatio * last_step_.norm();
  sliding_ = slides ? sliding_ + 1 : 0;
  if (sliding_ < kSlidingSteps || !move) {
    last_step_.swap(step_);
    has_last_ = true;
    return false;
  }
  image += (stretch_ - 1.0) * step_;
  moved_step_.swap(step_);
  confirming_ = true;
  sliding_ = 0;
  has_last_ = false;
  return true;
}

}  // namespace freeform
