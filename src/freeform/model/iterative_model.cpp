#include "freeform/model/iterative_model.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <limits>
#include <string>

namespace freeform {

void IterativeModel::run(const Progress& progress) {
  // One iteration per call is the same sequence as iterate(cap): the state carries over.
  const int cap = max_iterations();
  while (!state().converged && state().iterations < cap) {
    iterate(1, std::numeric_limits<double>::infinity(), nullptr);
    progress.step("nonlinear", static_cast<double>(state().iterations) / std::max(cap, 1));
  }
}

void IterativeModel::solve(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<RowMatrixX3d> out,
                           const Progress& progress) {
  if (out.rows() != n_free())
    throw InvalidInput("evaluate: output has " + std::to_string(out.rows()) + " rows, expected " +
                       std::to_string(n_free()));
  start(transforms, false, nullptr);
  run(progress);
  out = free_positions();
}

}  // namespace freeform
