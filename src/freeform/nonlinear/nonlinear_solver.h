// The nonlinear deformation model (docs/nonlinear.md): BCM made rotation-aware. BCM's operator
// splits as S_k = outer * L (bcm_system.h). Linear BCM keeps the rest's Laplacian coordinates
// L x_rest fixed, so a rotated handle shears the support; this model rotates every edge of
// them with the mean rotation (and scale) of its ends, as ARAP's right-hand side does (an
// edge to a constrained vertex with the row's own, so the boundary stays C^(k-1)):
//
//   A_pp x_p = outer * b(R) - A_pc x_c,   b_i(R) = sum_j w_ij (s_i R_i + s_j R_j) / 2 (x_j - x_i)_rest
//
// so order k and the boundary smoothness keep their meaning. At order 1 (ARAP's operator) and
// in the membrane term b(R) is ARAP's spokes-and-rims right-hand side instead (face_fans.h),
// whose edges to constrained vertices turn with the mean of both ends. It alternates a global step (one
// back-substitution with BCM's own factorization; one more for the volumes of the closed
// components, enclosed_volume.h) and a local step (R_i fitted to the edges of a neighbourhood
// that grows with the support, Newton steps from the last rotation, parallel); Anderson
// acceleration combines the last iterates (anderson.h). The first rotations come from the
// handles' rotations blended by BCM's own basis functions (harmonic guidance), so most edits
// converge in a few iterations. Identity transforms give the rest exactly; a rigid motion of
// every constraint moves everything rigidly.
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/mesh.h"
#include "freeform/model/iterative_model.h"
#include "freeform/regions/regions.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <atomic>
#include <memory>
#include <span>
#include <vector>

namespace freeform {

struct OneSided;
struct PartSettings;
struct SupportParts;

struct NonlinearOptions {
  // Per solve(); the report says when the cap stopped it. 500 lets all gallery edits but one
  // converge, where 200 stopped several (docs/nonlinear.md, "What the gallery found", 13 and
  // 25): a converged result depends on the edit alone, a capped one on the cap.
  int max_iterations = 500;
  // Converged when no vertex moved more than this fraction of the support's extent (bounding
  // box diagonal) in the last iteration.
  double tolerance = 1e-4;
  // Rings of neighbours whose edges the rotation fit of a vertex also uses (0: the 1-ring only;
  // -1: automatic, growing with sqrt(free vertices): 0.15 sqrt(free) within [3, 64] on a
  // detailed surface, 0.25 sqrt(free) within [2, 64] on a smooth multiresolution base). The
  // automatic settings count the free vertices of each connected part of the support apart
  // (part_settings.h): a part edited with others gets what it gets alone.
  // Measured (docs/nonlinear.md): 8 keeps the bar's and capsule's volume within 15 % where 0
  // loses up to 45 %, and converges in 3-10x fewer iterations; the S-bent plane's base (32k
  // free) needs ~40 to keep its bumps unfolded; on the gallery's limbs a wide fit squeezes the
  // bends (collapsed faces), a narrow one folds and converges worse.
  int rotation_smoothing = -1;
  // The rest is a smooth multiresolution base (set by nonlinear_base_model): the automatic width
  // above is the wider one.
  bool smooth_rest = false;
  // Keep the enclosed volume of every closed component with free vertices (a handle dragged
  // rather than turned or scaled adds or removes the volume its drag or scale moves,
  // enclosed_volume.h), each part of the support restoring what its own deformation changed;
  // open meshes are not affected.
  bool preserve_volume = true;
  // Weight of a membrane term (ARAP's energy) added to the global step's k-harmonic one, relative
  // to the operator at the scale of a ring (0: none; -1: automatic, 0.3 (500 / free) at k = 2 and
  // 0.03 (500 / free)^1.5 at k = 3, one power more below 500 free, at most 2: its share
  // shrinks as the support grows, like the fit's width). The order-k energy sees only the
  // Laplacian coordinates, which are nearly zero on smooth parts: it lets the inside of a bend or
  // a twisted limb compress freely. The membrane is ARAP's spokes-and-rims energy (face_fans.h);
  // its edges turn with their own 1-ring rotations (ARAP's) up to 10k free vertices, beyond with
  // the smoothed ones. Costs one more factorization at the start. Measured
  // (docs/nonlinear.md, "Gallery"): fewer than half the collapsed faces of the model without it;
  // the whole-cactus bend and the k = 3 pulls are clean.
  double membrane = -1.0;
  // Images of the local/global map combined by Anderson acceleration (anderson.h; 0: plain
  // iteration). Measured (docs/nonlinear.md): a third to two thirds fewer iterations on the
  // survey set-ups and the S-bent plane; 116 -> 61 on the editor benchmark's armadillo twist
  // (195 -> 139 on the bunny).
  int acceleration = 5;
  bool operator==(const NonlinearOptions&) const = default;
};

class NonlinearSolver final : public IterativeModel {
 public:
  // `linear` must have been built with keep_system (its factored system is taken over) from the
  // same mesh and regions. `rest`: the shape the model keeps (#V entries): the mesh's positions,
  // or the multiresolution base. Throws InternalError if `linear` kept no system.
  NonlinearSolver(const Mesh& mesh, const Regions& regions, BcmSolver& linear, const VertexData<Vec3>& rest,
                  const NonlinearOptions& options = {});
  ~NonlinearSolver() override;

  int n_free() const override { return n_free_; }
  int max_iterations() const override { return options_.max_iterations; }
  int n_movable() const { return n_movable_; }
  const NonlinearOptions& options() const { return options_; }

  // Starts a solve for one affine map per movable handle (applied to the rest). Cold: the
  // rotations come from the guidance field. Warm: the last solve's rotations, carried along by
  // the change of the guidance field (a drag: few iterations per frame). Throws InvalidInput
  // on a wrong count or a non-finite transform.
  // `linear`: optionally linear BCM's free rows for these transforms (BcmSolver::evaluate);
  // a warm start then also moves the current iterate by the change of linear BCM since the
  // last start: the first-order prediction a DragSession frame shows, as the start of the
  // next iterations.
  void start(std::span<const Eigen::Affine3d> transforms, bool warm, const RowMatrixX3d* linear) override;
  // Runs global/local iterations until converged, `max_iterations` more, or `budget_ms` spent.
  // `interrupt` (another thread's request, e.g. new transforms): checked after each global
  // step; when set, returns before the rotation fit (the iterate is valid, the step counted).
  // At the solve's cap (options().max_iterations) unconverged, the iterate becomes the image
  // with the smallest step since the start, and the state reports that step.
  const NonlinearState& iterate(int max_iterations, double budget_ms, const std::atomic<bool>* interrupt) override;
  const NonlinearState& state() const override { return state_; }
  Eigen::Ref<const RowMatrixX3d> free_positions() const override;

 private:
  struct Data;
  std::unique_ptr<Data> d_;
  NonlinearOptions options_;
  NonlinearState state_;
  int n_free_ = 0;
  int n_movable_ = 0;

  void fit_rotations();
  void fit_growth();
  void keep_volumes();
  void start_volumes(std::span<const Eigen::Affine3d> transforms, std::span<const Vec3> omega,
                     std::span<const double> handle_s);
  void add_membrane(const SupportParts& parts, const std::vector<PartSettings>& settings);
  void arap_rows(const std::vector<Eigen::Matrix3d>& rot, Eigen::MatrixXd& out,
                 const std::vector<OneSided>* targets = nullptr);
};

// The model for MultiresOptions::model: the nonlinear model on the multiresolution base,
// which keeps that smooth rest base (NonlinearOptions::smooth_rest).
IterativeModelFactory nonlinear_base_model(const NonlinearOptions& options);

}  // namespace freeform
