#include "freeform/nonlinear/anderson.h"

#include <Eigen/Cholesky>

#include <algorithm>

namespace freeform {
namespace {
// Relative Tikhonov term of the m x m least-squares system: nearly parallel residual
// differences (a stagnating iteration) would otherwise give huge, cancelling coefficients.
constexpr double kRegularization = 1e-10;
}  // namespace

AndersonAcceleration::AndersonAcceleration(Eigen::Index dim, int m)
    : m_(m), dg_(dim, m), df_(dim, m), last_g_(dim), last_f_(dim), f_(dim) {}

void AndersonAcceleration::reset() {
  count_ = 0;
  newest_ = -1;
  has_last_ = false;
}

bool AndersonAcceleration::next(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g,
                                bool combine) {
  if (m_ <= 0) return false;
  f_ = g - x;
  const Eigen::VectorXd& f = f_;
  if (has_last_ && f.squaredNorm() > last_f_.squaredNorm()) {
    // The combined iterate was worse than the one before it: start over from the plain image.
    reset();
  } else if (has_last_) {
    newest_ = (newest_ + 1) % m_;
    count_ = std::min(count_ + 1, m_);
    dg_.col(newest_) = g - last_g_;
    df_.col(newest_) = f - last_f_;
  }
  last_g_ = g;
  last_f_ = f;
  has_last_ = true;
  if (count_ == 0 || !combine) return false;
  const auto df = df_.leftCols(count_);
  Eigen::MatrixXd normal = df.transpose() * df;
  normal.diagonal().array() += kRegularization * normal.diagonal().maxCoeff() + 1e-300;
  const Eigen::VectorXd gamma = normal.ldlt().solve(df.transpose() * f);
  if (!gamma.allFinite()) {
    reset();
    return false;
  }
  g.noalias() -= dg_.leftCols(count_) * gamma;
  return true;
}

}  // namespace freeform
