// The precomputing BCM solver (docs/bcm.md): construct once (assemble + factor +
// 3 + 4M solves), then evaluate(transforms) per frame as a dense product.
//
//   p = P_const + sum_m B_m T_m(F0_m)      P_const: P x 3, B_m: P x 4, F0_m: 4 x 3
// F0_m is a virtual affine frame of movable handle m (centroid c, c + s e1, c + s e2, c + s e3
// with s its extent); handle vertices are affine combinations of it. Immovable handles are
// folded into the constant part.
#pragma once

#include "freeform/bcm/bcm_analysis.h"
#include "freeform/bcm/bcm_system.h"
#include "freeform/bcm/settings.h"
#include "freeform/common/phase_clock.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/mesh.h"
#include "freeform/numerics/sparse_solver.h"
#include "freeform/regions/regions.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace freeform {

// Above this forward-error estimate (relative to the bounding-box diagonal) the CLI and the
// editor warn.
constexpr double kForwardErrorWarning = 1e-6;

struct BcmStats {
  std::string solver;      // SparseSolver::name()
  bool symmetric = false;
  int free = 0;            // P
  int constrained = 0;     // C: constrained vertices in the system
  double assembly_ms = 0, factorization_ms = 0, basis_ms = 0;  // basis: the first solve
  bool analysis_ahead = false;  // the factorization used the symbolic analysis run ahead
  double analysis_ahead_ms = 0;  // that analysis' own time, on its thread (overlapping the above)
  double analysis_ahead_cpu_ms = 0;  // its CPU time, with the threads its ordering used
  std::string ordering;          // SparseSolver::ordering(): how the rows were ordered
  double factor_nonzeros = 0;    // the Cholesky factor's (0 for other solvers)
  // Wall and CPU time per phase, in order: parametrization (anisotropic only), assembly,
  // factorization, basis, refinement (common/phase_clock.h).
  std::vector<Phase> phases;
  double residual = 0;     // max over right-hand sides of |A_pp X - B| / |B| (relative)
  // Iterative refinement against the unassembled operator (bcm/refinement.h): steps, whether
  // it met its tolerance, and the forward-error estimate it leaves (the last correction, as a
  // position error at the rest transforms, relative to the mesh's bounding-box diagonal).
  int refinement_steps = 0;
  bool refinement_converged = false;
  double forward_error = 0;
  double unrefined_error = 0;  // the same measure of the first correction: the plain solve's error
  double refinement_ms = 0;
  // docs/operators.md diagnostics of the assembled faces: degenerate ones (no weights, no
  // area) and cotangents clamped on needle-thin ones.
  int degenerate_faces = 0;
  int clamped_cotangents = 0;
  // Anisotropic bending (settings.anisotropic; param/anisotropic.h): whether its operator was
  // used, the principal extents (major, minor) of the conformal map before equalizing, why it
  // fell back to the isotropic operator (empty if used or not requested), its wall time.
  bool anisotropic = false;
  std::array<double, 2> principal_extents{0.0, 0.0};
  std::string anisotropic_fallback;
  double parametrization_ms = 0;
};

// Why an order-k system on these free vertices may be beyond double precision: their faces'
// thinnest triangle, named where its smallest corner is below 1 degree (a CAD part's needle
// fans); empty otherwise.
std::string needle_cause(const Mesh& mesh, const std::vector<Vertex>& free, int order);

// The support at the rest transforms (every handle where it stands) from one 3-column solve,
// refined as BcmSolver's, without the basis that frames need: for a fill solved once (the
// multiresolution's membrane, multires/operator_shape.h). Isotropic operator only.
struct BcmRestSolution {
  std::vector<Vertex> free;    // rows of the system (BcmSolver::free_vertices()' order)
  VertexData<Vec3> positions;  // #V: the solution on the free vertices, the mesh elsewhere
};
BcmRestSolution bcm_rest_solution(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                                  const Progress& progress = {});

// The factored system, kept on request for a model that solves it again with new right-hand
// sides (the nonlinear model, nonlinear/nonlinear_solver.h). Rows and columns as in BcmSystem.
struct BcmFactoredSystem {
  std::vector<Vertex> constrained;  // columns of a_pc
  Eigen::SparseMatrix<double> a_pc;
  Eigen::SparseMatrix<double, Eigen::RowMajor> lap;  // S_k = outer * lap (BcmSystem)
  Eigen::SparseMatrix<double> outer;
  SparseSolver solver;              // factors A_pp (it holds A_pp's lower triangle)
  int order = 0;                    // k: S_k's order
  std::vector<double> smoothness;   // per constrained vertex: its boundary smoothness c (boundary_band.h)
};

// Order of the free rows (free_vertices(), constant_part(), basis()). BreadthFirst keeps mesh
// neighbours near each other in memory, which the per-vertex arrays of multiresolution and
// the nonlinear model follow; ByIndex makes the frame's scatter into a mesh's positions one
// sequential write (the plain linear model: 2x faster at 140k-300k free, docs/benchmarks.md).
// The system is assembled and factored breadth-first either way.
enum class RowOrder { BreadthFirst, ByIndex };

class BcmSolver {
 public:
  using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  // Throws InvalidInput / SolverError with a message that says what to fix, Cancelled when
  // progress.cancel is set (checked between the stages; reports fractions up to 0.9).
  // `operator_positions` (default: the mesh's): the shape the operator's cotangents and areas
  // come from; constraints and frames always use the mesh's positions. Multiresolution passes
  // its smooth base here, so the detail's metric does not steer the bend (docs/multires.md).
  // keep_system: keep the factored system for release_system() (the nonlinear model); its
  // rows are breadth-first, so rows must then be RowOrder::BreadthFirst (else InvalidInput).
  // `analysis`: the symbolic factorization started ahead by the caller (bcm_analysis.h) for
  // this mesh, regions and settings; null: the solver starts one itself before the assembly.
  BcmSolver(const Mesh& mesh, const Regions& regions, const BcmSettings& settings, const Progress& progress = {},
            const VertexData<Vec3>* operator_positions = nullptr, bool keep_system = false,
            RowOrder rows = RowOrder::BreadthFirst, BcmAnalysis* analysis = nullptr);

  int n_free() const;
  int n_movable() const;  // number of transforms evaluate() expects, in handle order
  const std::vector<Vertex>& free_vertices() const;
  Vec3 handle_centroid(int movable) const;  // default pivot of manipulator `movable`
  const BcmStats& stats() const { return stats_; }

  // Positions of the free vertices (P x 3, row i = free_vertices()[i]) for one affine map per
  // movable handle (transforms.size() == n_movable(), T_m applied to the rest frame).
  // No allocation; parallel over rows (common/parallel.h), AVX2 where the CPU has it.
  // out must be P x 3.
  // Throws InvalidInput on a wrong count, wrong out size or a non-finite transform.
  // Thread safety: concurrent calls on one solver are safe for up to kStackHandles movable
  // handles (the 4M x 4 padded frame matrix lives on the stack); with more, a preallocated member is
  // used and evaluate() must not be called concurrently on the same solver.
  void evaluate(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<RowMatrixX3d> out) const;
  // Writes the free and movable-handle vertices of `positions` (#V entries; handle vertices
  // move rigidly, h' = T_m(h)); fixed and immovable-handle vertices are untouched.
  void evaluate(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions) const;
  // Only the movable-handle vertices (h' = T_m(h)); transforms already checked by the caller.
  void move_handles(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions) const;
  static constexpr int kStackHandles = 32;

  // The precomputed parts (tests, multiresolution).
  const RowMatrixX3d& constant_part() const { return constant_; }
  // B: P x 4M, columns 4m..4m+3 belong to movable handle m.
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& basis() const { return basis_; }
  const std::array<Vec3, 4>& frame(int movable) const { return frames_[static_cast<std::size_t>(movable)]; }
  // The factored system if built with keep_system (else null); the caller takes it over.
  std::unique_ptr<BcmFactoredSystem> release_system() { return std::move(system_); }

 private:
  // The constructor's phases: each movable handle's virtual frame (frames_, centroids_, the
  // handle vertices; returns the frames' extents), the constrained values [x_c | Q_m], and the
  // rows put in vertex order (RowOrder::ByIndex).
  std::vector<double> handle_frames(const Mesh& mesh, const Regions& regions);
  Eigen::MatrixXd constrained_values(const Mesh& mesh, const Regions& regions, const std::vector<Vertex>& constrained,
                                     const std::vector<double>& extent) const;
  void sort_rows_by_vertex(Eigen::MatrixXd& x);

  BcmStats stats_;
  std::vector<Vertex> free_;
  RowMatrixX3d constant_;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> basis_;
  std::vector<std::array<Vec3, 4>> frames_;
  std::vector<Vec3> centroids_;
  // Movable handle vertices and their owner, to move them rigidly with T_m.
  std::vector<Vertex> handle_vertices_;
  std::vector<int> handle_owner_;
  std::vector<Vec3> handle_rest_;
  int n_vertices_ = 0;
  std::unique_ptr<BcmFactoredSystem> system_;
  mutable std::vector<double> scratch_;  // 16 M doubles (G padded to 4 lanes), only if M > kStackHandles (see evaluate)

  const double* frame_matrix(std::span<const Eigen::Affine3d> transforms, double* stack_buffer) const;
  template <class Store>
  void run(const double* g, const Store& store) const;
};

}  // namespace freeform
