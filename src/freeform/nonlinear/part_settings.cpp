#include "freeform/nonlinear/part_settings.h"

#include "freeform/nonlinear/nonlinear_solver.h"
#include "freeform/nonlinear/ring_smoothing.h"

#include <algorithm>
#include <cmath>

namespace freeform {
namespace {

// Automatic rotation smoothing: passes grow with the support's width in edges (~sqrt of its
// vertex count), so the smoothed patch covers a similar part of it at any resolution (each
// pass widens the fit's kernel by about a ring's square root). Measured (docs/nonlinear.md):
// - a smooth multiresolution base: the S-bent plane (32k free) folds its first bumps below
//   ~40 passes: 0.25 sqrt(free);
// - a detailed surface (the gallery's limbs, 40-23,000 free): 0.25 sqrt(free) squeezed the
//   bends (4,040 / 5,439 collapsed faces at k = 2 / 3), 0.15 sqrt(free) from 3 passes on
//   collapses 37 % fewer with 3 % fewer folds; narrower still folds more and converges worse.
// The cap bounds the cost per iteration.
constexpr double kSmoothingPerSqrtFree = 0.15, kBaseSmoothingPerSqrtFree = 0.25;
constexpr int kMinSmoothingRings = 3, kMinBaseSmoothingRings = 2, kMaxSmoothingRings = 64;
// Automatic membrane weight (NonlinearOptions::membrane): kMembrane[k] (kMembraneFree / free) to the
// power kMembranePower[k], one power more below kMembraneFree, at most kMaxMembrane, so that the
// membrane's share shrinks as the support grows, like the fit's width. Chosen on the gallery
// (docs/nonlinear.md, 12 to 14 and 24): heavier weights squeeze fewer faces but fold or cycle on
// the survey's bar, S-bent plane and capsule; a limb only a few rings across needs more of it,
// up to twice the bending term's weight.
constexpr double kMembrane[] = {0.0, 0.0, 0.3, 0.03}, kMembranePower[] = {0.0, 0.0, 1.0, 1.5};
constexpr double kMembraneFree = 500.0, kMaxMembrane = 2.0;
// The membrane turns with its own 1-ring rotations (ARAP's) up to this many free vertices;
// beyond, with the bending term's smoothed field: on large supports the 1-ring rotations made the
// editor benchmark's drags settle far later, at k = 2 and 3 alike (docs/nonlinear.md, "What the
// gallery found", 22).
constexpr int kLocalMembraneMaxFree = 10000;
// How the membrane's targets follow the edges' stretch (face_fans.h). With its own 1-ring
// rotations: compressed edges pushed out by 1.25 times their compression, stretched ones pulled
// back halfway: limbs keep their cross-sections and crooks fold less (docs/nonlinear.md, "What
// the gallery found", 21, 35, 40 and 54; 1.5 times folded a spider's leg where ARAP folds
// nothing). From kLeanFrom free vertices on, where the 1-ring rotations alone converged slowly
// and with a push of half the compression folded the subdivided armadillo's twists (until
// item 56 the push fell to that from 5,000 to 8,000 free vertices), each row's membrane turns
// halfway to the smoothed field (kFieldLean, blended in by kLeanFull): with the field alone
// more faces collapsed at k = 2 (item 56). Stretched edges are pulled back by only a fifth of
// their stretch up to kReleasedStretchFull, blended into half by kReleasedStretchNone:
// released on larger supports, the survey's twisted bar (1,640 free) buckled in its middle
// (item 40).
// Fed back through the right-hand side alone, that push flips a mode's sign every iteration, so
// there the factored operator holds kLaggedMembrane more of the membrane's weight and the
// right-hand side gives it back at the current iterate: the fixed points stay, and for a
// compressed edge the feedback falls to a fifth (as large a lag took more iterations, item 54).
// With the smoothed field (larger supports still) a stretch is resisted fully and the push's
// onset is smooth: releasing stretch, or a kink at the rest length, made the editor benchmark's
// bunny twist settle in 40-300 iterations instead of 25-28; without the push the subdivided
// armadillo's knee crumpled at C0 (item 28).
constexpr OneSided kLocalMembrane{1.25, 0.5}, kFieldMembrane{0.5, 0.0, 0.1};
constexpr double kReleasedStretch = 0.8, kReleasedStretchFull = 1000.0, kReleasedStretchNone = 1500.0;
constexpr double kFieldLean = 0.5, kLeanFrom = 5000.0, kLeanFull = 6000.0;
constexpr double kLaggedMembrane = 1.0;
// Where the field bends rather than twists (FaceFans::where_bent), a stretch is accepted wholly
// with the 1-ring rotations: the outside of a crook stretches and its inside folds less
// (docs/nonlinear.md, "What the gallery found", 48).
constexpr double kBentStretchShare = 1.0;
// Where a row's 1-ring fit is ill-conditioned (fit_conditioning below this; 1/4 on a flat, even
// fan), its membrane turns with the smoothed field: the 1-ring rotation of a fan folded flat or
// of a needle's corner swings from one iteration to the next, and runs cycled to the cap (a
// small handle at the corner of a sheet, the engine block's needles). At 0.2 more faces
// collapsed on meshes the gallery does not use (docs/nonlinear.md, "What the gallery found", 51).
constexpr double kFieldBelowConditioning = 0.15;

}  // namespace

PartSettings part_settings(int free, int order, const NonlinearOptions& options) {
  PartSettings s;
  const double per_sqrt = options.smooth_rest ? kBaseSmoothingPerSqrtFree : kSmoothingPerSqrtFree;
  s.smoothing_rings =
      options.rotation_smoothing >= 0
          ? options.rotation_smoothing
          : std::clamp(static_cast<int>(std::lround(per_sqrt * std::sqrt(double(free)))),
                       options.smooth_rest ? kMinBaseSmoothingRings : kMinSmoothingRings, kMaxSmoothingRings);
  s.membrane = options.membrane;
  if (s.membrane < 0.0) {  // automatic; order 1 is a membrane already
    const auto k = static_cast<std::size_t>(std::clamp(order, 0, 3));
    const double ratio = kMembraneFree / std::max(free, 1);
    s.membrane = std::min(kMembrane[k] * std::pow(ratio, kMembranePower[k]) * std::max(ratio, 1.0), kMaxMembrane);
  }
  s.local_membrane = free <= kLocalMembraneMaxFree;
  if (!s.local_membrane) {
    s.targets = kFieldMembrane;
    return s;
  }
  const auto up = [free](double from, double to) { return std::clamp((free - from) / (to - from), 0.0, 1.0); };
  const double released = 1.0 - up(kReleasedStretchFull, kReleasedStretchNone);
  s.targets = kLocalMembrane;
  s.targets.stretch_share += released * (kReleasedStretch - kLocalMembrane.stretch_share);
  s.targets.bent_stretch_share = kBentStretchShare;
  // Lengths between the rest's and a grown target taken as they are (OneSided::growth_taken) only
  // where the membrane turns with its own 1-ring rotations alone: with the lean the subdivided
  // armadillo's grown limb iterated far longer (docs/nonlinear.md, "What the gallery found", 64).
  s.targets.growth_taken = free <= kLeanFrom;
  s.lagged = kLaggedMembrane;
  s.field_below = kFieldBelowConditioning;
  s.field_lean = kFieldLean * up(kLeanFrom, kLeanFull);
  return s;
}

SupportParts support_parts(const Eigen::SparseMatrix<double, Eigen::RowMajor>& lap, int n_free) {
  SupportParts parts;
  int count = 0;
  parts.of_row = connected_rows(lap, count);
  parts.free.assign(static_cast<std::size_t>(count), 0);
  for (int i = 0; i < n_free; ++i) ++parts.free[static_cast<std::size_t>(parts.of_row[static_cast<std::size_t>(i)])];
  return parts;
}

}  // namespace freeform
