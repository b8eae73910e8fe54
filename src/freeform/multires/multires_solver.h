// Multiresolution editing (docs/multires.md; Botsch & Kobbelt 2004, section 5): the support
// is split into a smooth base (the BCM solution with unmoved handles, same k, smoothness,
// anisotropy and regions) and detail encoded per free vertex relative to that base. Per frame
// the base is rebuilt from the precomputed BCM basis, its vertex normals are recomputed in the
// support and its first ring, and every free vertex is rebuilt from its encoding.
//
// Encodings (docs/multires.md):
//  - vertex frame (the linear model's where the detail stands on its base): the detail vector of
//    free vertex i in a frame at base vertex i (vertex_frame.h), over the paper's base, the BCM
//    solution on the detailed mesh;
//  - normal displacement (elsewhere, and the nonlinear model's over the smooth operator shape):
//    base triangle t = (a, b, c), barycentrics (u, v, w), signed height h with
//    x = sum_corner bary * (corner + h * corner_normal); found by the cubic of section 6
//    over the faces around the vertex (growing rings), smallest |h| wins;
//  - local frame (fallback where no triangle qualifies): offset in the frame (e, n x e, n) at
//    the nearest base vertex, e = a projected edge.
// The identity manipulator reproduces the input to rounding (~1e-16 of the mesh size).
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/bcm/settings.h"
#include "freeform/common/progress.h"
#include "freeform/mesh/mesh.h"
#include "freeform/model/iterative_model.h"
#include "freeform/multires/operator_shape.h"
#include "freeform/multires/vertex_frame.h"
#include "freeform/regions/regions.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <span>
#include <vector>

namespace freeform {

struct MultiresOptions {
  // Automatic: for the linear base VertexFrame where the detail stands on its base (the smooth
  // operator shape exists, operator_shape.h), else Normal over the detailed mesh's operator; for
  // the nonlinear base Normal over the smooth shape where it exists.
  // VertexFrame: each free vertex's detail in a frame at its own base vertex, over the BCM base
  // on the detailed mesh (the paper's).
  // Normal: normal displacement where a triangle qualifies, local frame elsewhere.
  // LocalFrame: local frame for every vertex (cheaper, rotates detail with the base normal only).
  enum class Encoding { Automatic, VertexFrame, Normal, LocalFrame };
  Encoding encoding = Encoding::Automatic;
  int search_rings = 3;  // candidate faces: around vertices within 0..this-1 rings of the nearest base vertex
  double barycentric_tolerance = 1e-4;   // a root counts if every barycentric >= -tolerance
  // Set: the base follows this iterating model (e.g. nonlinear_base_model(), the nonlinear one),
  // built over the base's system and the smooth rest base, instead of the linear basis; the
  // detail rides along unchanged.
  IterativeModelFactory model;
};

struct MultiresStats {
  double decomposition_ms = 0;  // base + encoding + operator_shape_ms (excludes the BCM precomputation)
  int free = 0;                 // encoded vertices (= BCM free vertices)
  int normal_encoded = 0;       // vertices with a normal displacement
  int fallback = 0;             // vertices with the local-frame fallback
  int vertex_frames = 0;        // vertices encoded in the frame of their own base vertex
  double max_height = 0;        // max |h| of the normal displacements, or of the vertex frames' normal offsets (mesh units)
  int rest_folded = 0;          // encodings already folded at rest (det of the offset map <= 0)
  // The base's operator (operator_shape.h): on the smooth foot-point shape, or (false) on the
  // detailed mesh, with the reason where the shape was wanted but could not be used (empty for
  // vertex frames: they use the detailed mesh's operator by design); the foot-point shape's wall
  // time (a k = 1 factorization).
  bool smooth_operator = false;
  std::string operator_fallback;
  double operator_shape_ms = 0;
  // Set by EditSolver for the nonlinear model where the detail overhangs its base (the foot
  // points fold): the model then keeps the detailed mesh itself and nothing is decomposed
  // (docs/nonlinear.md, "Detail that overhangs its base").
  bool detail_by_model = false;
};

// Found after a reconstruction (see problems()).
struct MultiresProblems {
  int flipped = 0;   // support triangles facing along the base at rest (cos > 0.2) that now face against it
  // Free vertices whose detail the frame flattened: the base is bent tighter than their height
  // there (a focal point of the offset surface), so h was lowered just enough to keep the
  // offset map from folding over (multires::safe_height) instead of tearing.
  int overlaps = 0;
  bool ok() const { return flipped == 0 && overlaps == 0; }
};

// Wall times of the last evaluate(): the base from the BCM basis (the dense product) and the
// detail reconstruction (normals + encodings), in milliseconds.
struct MultiresTimings {
  double base_ms = 0;
  double detail_ms = 0;
};

class MultiresSolver {
 public:
  // Builds the BcmSolver (throws like it: InvalidInput / SolverError) and decomposes the
  // support. Cost: the BCM precomputation plus O(support) candidate searches (parallel).
  // Cancelled when progress.cancel is set (checked between stages, "detail" last).
  MultiresSolver(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                 const MultiresOptions& options = {}, const Progress& progress = {});
  // The same with the base's operator shape already computed (base_operator_shape) and,
  // optionally, the BCM system's symbolic analysis started before it (bcm/bcm_analysis.h).
  MultiresSolver(const Mesh& mesh, const Regions& regions, const BcmSettings& settings, const MultiresOptions& options,
                 const Progress& progress, const OperatorShape& shape, BcmAnalysis* analysis = nullptr);

  const BcmSolver& bcm() const { return bcm_; }
  int n_movable() const { return bcm_.n_movable(); }
  const MultiresStats& stats() const { return stats_; }
  // Per free vertex (BcmSolver::free_vertices() order): true where the local frame was used.
  std::vector<bool> fallback_mask() const;

  // Writes free and movable-handle vertices of `positions` (#V entries): base from the basis,
  // detail added back. Fixed and immovable-handle vertices are untouched. transforms as for
  // BcmSolver::evaluate (one affine map per movable handle, applied to the rest frame).
  // No allocation, O(support), parallel (OpenMP static schedule above a size threshold).
  // Uses workspace members: do not call evaluate()/problems() concurrently on one solver.
  // Throws InvalidInput on a wrong transform count, a non-finite transform or a wrong size.
  // With an iterating base: one cold solve of that model (to convergence or its cap), stepping
  // `progress` after each iteration.
  void evaluate(std::span<const Eigen::Affine3d> transforms, VertexData<Vec3>& positions,
                const Progress& progress = {}) const;

  // The iterating model of the base (null for the linear base). A drag runs its start/iterate
  // itself (DragSession) and calls reconstruct() to show an iterate with its detail.
  IterativeModel* model() const { return model_.get(); }
  // Like evaluate(), with the base's free rows given (P x 3, an iterate of model(); no solve).
  // Uses the same workspace as evaluate(). Throws InvalidInput without an iterating base.
  void reconstruct(std::span<const Eigen::Affine3d> transforms, Eigen::Ref<const BcmSolver::RowMatrixX3d> base,
                   VertexData<Vec3>& positions) const;

  // Flipped triangles and local overlaps of `positions` as written by the last evaluate()
  // (it uses that call's base). Counts only changes against the rest state. O(support).
  MultiresProblems problems(const VertexData<Vec3>& positions) const;
  const MultiresTimings& last_timings() const { return timings_; }

  // Base surface of the last evaluate() (#V entries written for every vertex the solver
  // touches; others copied from `positions`): tests and visualization.
  void base_positions(VertexData<Vec3>& positions) const;

 private:
  using RowMatrixX3d = BcmSolver::RowMatrixX3d;
  // What the per-frame loop reads (56 bytes; the rest of an encoding is in cold arrays).
  struct Code {
    std::array<int, 3> corner;  // local indices; fallback: {anchor, edge neighbour, -1}
    std::array<double, 3> w;    // barycentrics; fallback: coordinates in the frame
    double h = 0;               // height (normal encoding)
    // Below this det of the offset map the detail nears a fold (min_ratio_ * rest a0): a
    // one-cross-product test; -inf: never flattened.
    double min_det = -std::numeric_limits<double>::infinity();
  };

  BcmSolver bcm_;
  std::unique_ptr<IterativeModel> model_;
  MultiresStats stats_;
  int n_vertices_ = 0;
  int n_free_ = 0;
  // Local vertices: rows [0, P) the free vertices (BCM order), then movable handle vertices,
  // then constant ones (fixed, immovable handles) needed for normals.
  std::vector<int> local_global_;          // global vertex index per local vertex
  std::vector<int> handle_owner_;          // movable index per moving handle row (after P)
  std::vector<Vec3> handle_rest_;          // rest position per moving handle row
  int n_moving_ = 0;                       // P + movable handle vertices
  std::vector<std::array<int, 3>> faces_;  // local faces (corners as local indices)
  std::vector<int> normal_vertices_;       // local vertices whose normal is recomputed
  std::vector<int> normal_faces_;          // local faces around them (rows of fnormal_)
  std::vector<int> vf_offset_, vf_faces_;  // CSR: rows of fnormal_ around normal_vertices_[k]
  std::vector<Code> codes_;                // per free vertex
  bool vertex_frames_ = false;             // codes_ hold vertex-frame coordinates (w; corner[0] = i)
  // Vertex frames (multires/vertex_frame.h), per free vertex (CSR): its ring (local vertices)
  // and the ring's rest 2D coordinates (float: half the bytes per frame; rest and frame read the
  // same values, so the identity stays exact).
  std::vector<int> ring_offset_, ring_;
  std::vector<float> ring_weight_;
  std::vector<double> frame_w_;  // vertex frames: each free vertex's frame coordinates (0 where unframed)
  std::vector<int> unframed_;    // vertex frames: free vertices placed by their plain offset
  // Per free vertex: det / a0 along the height ray may not fall below this (multires::safe_height),
  // a fixed fraction of its rest value so the rest never flattens; -inf: never flattened.
  std::vector<double> min_ratio_;
  std::vector<std::int8_t> rest_sign_;     // sign of det(offset map Jacobian) at rest (normal encoding)
  std::vector<int> detail_faces_;          // local faces with a free corner (problem check)
  std::vector<int> detail_face_global_;    // their 3 global corners, flattened
  std::vector<std::int8_t> detail_rest_sign_;
  // Workspace of evaluate().
  mutable RowMatrixX3d base_;     // local positions, rows = local vertices
  mutable RowMatrixX3d fnormal_;  // per normal face (area weighted)
  mutable RowMatrixX3d normal_;   // per local vertex (unit; rows of other vertices unused)
  mutable RowMatrixX3d tangent_;  // per free vertex with vertex frames: P g - n x h, not normalized
  mutable MultiresTimings timings_;
  mutable int flattened_ = 0;  // vertices whose detail the last evaluate() flattened

  enum class Base { Linear, ModelSolve, Given };
  void update_base(std::span<const Eigen::Affine3d> transforms, Base source,
                   const Eigen::Ref<const RowMatrixX3d>* given = nullptr, const Progress& progress = {}) const;
  void add_detail(VertexData<Vec3>& positions) const;  // the free vertices by encoding, then the handles
  int add_displaced_detail(Vec3* out) const;          // normal displacement / local frames; returns flattened
  void add_vertex_frame_detail(Vec3* out) const;
  // The constructor's phases (multires_solver.cpp).
  struct LocalAdjacency;
  void build_local(const Mesh& mesh, const Regions& regions, const VertexData<int>& dist, int normal_rings,
                   VertexData<int>& local, FaceData<int>& local_face);
  void select_normal_vertices(const Mesh& mesh, const FaceData<int>& local_face, const std::vector<char>& wanted);
  void encode_vertex_frames(const Mesh& mesh, const VertexData<int>& local, const FaceData<int>& local_face);
  struct EncodeScratch;
  void encode_displaced(const Mesh& mesh, const LocalAdjacency& adjacency, bool normal_encoding,
                        const MultiresOptions& options, const Progress& progress);
  int nearest_base_vertex(int i, const Vec3& x, const LocalAdjacency& adjacency) const;
  bool encode_on_faces(int i, const Vec3& x, int start, const LocalAdjacency& adjacency,
                       const MultiresOptions& options, EncodeScratch& scratch);
  void encode_in_frame(int i, const Vec3& x, int start, const LocalAdjacency& adjacency);
  void count_codes();
  void set_detail_rest_signs(const Mesh& mesh);
  multires::RingStencil ring_stencil() const;  // the free vertices' rings, for their frames' tangents
  // Rebuilds free vertex i with its height lowered by multires::safe_height; 1 if it was lowered.
  int flatten_detail(int i, Vec3* out) const;
  void update_normals() const;
  Vec3 base_face_normal(int f) const;  // of local face f on the current base, area weighted
};

}  // namespace freeform
