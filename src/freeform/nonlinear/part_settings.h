// The nonlinear model's automatic settings (NonlinearOptions' -1 values), chosen for each
// connected part of the support from that part's own free vertices: an edit of two limbs gives
// each limb the settings it gets when edited alone, so a limb's result does not depend on which
// other, unconnected parts are edited with it (docs/nonlinear.md, "What the gallery found", 47).
#pragma once

#include "freeform/nonlinear/face_fans.h"

#include <Eigen/SparseCore>

#include <vector>

namespace freeform {

struct NonlinearOptions;

struct PartSettings {
  int smoothing_rings = 0;      // passes of the rotation fit's smoothing (ring_smoothing.h)
  double membrane = 0.0;        // the membrane's weight relative to the bending term's, at a ring's scale
  bool local_membrane = false;  // the membrane turns with its own 1-ring rotations, else with the field's
  OneSided targets;             // how the membrane's targets follow the edges' stretch (face_fans.h)
  double lagged = 0.0;          // extra membrane weight held by the operator, given back on the right-hand side
  // With local_membrane: a row whose own 1-ring fit is conditioned below this (fit_conditioning,
  // rotation.h) turns its membrane edges with the smoothed field instead, wholly at half of it.
  double field_below = 0.0;
  // With local_membrane: the least share of the smoothed field's rotation in every row's
  // membrane rotation (a slerp from its own 1-ring fit).
  double field_lean = 0.0;
};

// The settings of a part of `free` free vertices at order `order`; options' non-negative
// rotation_smoothing and membrane are taken as given.
PartSettings part_settings(int free, int order, const NonlinearOptions& options);

// The connected parts of the rows of `lap` (rows adjacent through off-diagonal columns that are
// rows too): the free vertices [0, n_free) and the constrained ring the fit also sums.
struct SupportParts {
  std::vector<int> of_row;  // per row, its part (0 .. free.size() - 1, numbered by first row)
  std::vector<int> free;    // per part, its rows below n_free
  int count() const { return static_cast<int>(free.size()); }
};
SupportParts support_parts(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int n_free);

}  // namespace freeform
