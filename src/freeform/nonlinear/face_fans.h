// The triangle fans of the nonlinear model's rows, for ARAP's spokes-and-rims energy (Chao et
// al. 2010; CGAL's Surface_mesh_deformation default): each vertex's cell is its fan of
// triangles with all three edges of each, not only the spokes to its neighbours. With it our
// order 1 with the 1-ring fit folds no more than CGAL's ARAP on the gallery, where the spokes
// folded 2.5 times as much (docs/nonlinear.md, "What the gallery found", 12).
#pragma once

#include "freeform/mesh/mesh.h"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>

#include <array>
#include <span>
#include <vector>

namespace freeform {

// How the membrane's target follows an edge's stretch s along it (FaceFans::target_scale): a
// compressed edge (s < 1) is pushed out to 1 + compression_gain (1 - s) of its target, a
// stretched one pulled back to 1 + stretch_share (s - 1). With onset > 0 the push starts
// smoothly: compression_gain (1 - s)^2 / (2 onset) up to a compression of onset, then the line
// shifted by onset / 2 (its slope continuous). The defaults were chosen on the gallery
// (docs/nonlinear.md, "What the gallery found", 21 and 35): the solver takes a compression gain
// of 1 on small supports only, where it keeps cross-sections; accepting all of the stretch lets
// stretched regions drift for hundreds of iterations.
struct OneSided {
  double compression_gain = 0.5;
  double stretch_share = 0.5;
  double onset = 0.0;
  // The stretch share on a face where the rotation field bends rather than twists
  // (FaceFans::where_bent); no effect at or below stretch_share.
  double bent_stretch_share = 0.0;
  // Where a handle grows the support (growth_taken, on small supports): the scale in the face's
  // targets, where above 1 (NonlinearSolver sets it per face and iteration). An edge between its
  // rest length and its grown target is then taken as it is, and a shorter one pushed out from
  // its rest length: growth is not forced on a band that the geometry shortens, next to a fixed
  // rim (docs/nonlinear.md, "What the gallery found", 64).
  bool growth_taken = false;
  double grown = 1.0;
};

class FaceFans {
 public:
  using Laplacian = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  // Rows [0, lap.rows()) in the local numbering of `lap` (local[v], -1 outside the patch;
  // global[i]: local vertex i's mesh vertex). A face enters a row's fan when all its corners
  // are local. `rest`: the local rest positions (3 per vertex), whose cotangents weight the fit.
  FaceFans(const Mesh& mesh, const VertexData<int>& local, std::span<const Vertex> global, const double* rest,
           const Laplacian& lap);

  // The rotation fit's covariance of row i: sum over its fan of w_ab (x_a - x_b)(r_a - r_b)^T
  // for the three edges of each face, w the positive part of the cotangent opposite the edge
  // plus a floor (so that no edge of a needle triangle drops out of the fit). Summed as
  // sum_a (x_a - x_i) g_a^T over the ring, g_a the rest's part gathered once.
  Eigen::Matrix3d covariance(int i, const double* x) const;

  // ARAP's right-hand side of row i (a free row) as rotated minus rest Laplacian coordinates:
  // each face's two edges at i turned by the mean M of its three corners' rot (scale times
  // rotation minus the identity; constrained corners with their own), given per face in
  // `means` (mean()): the gradient of the spokes-and-rims energy. lap's weight of each edge is
  // split between its faces in proportion to their |cotangent|, so a common rot of all corners
  // gives rot * (lap rest)_i exactly.
  Eigen::Vector3d rotated(int i, const double* rest, const std::vector<Eigen::Matrix3d>& means) const;

  // The same with one-sided targets at the current positions x: each edge's target M r also
  // scaled by target_scale() of its stretch along it (exactly 1 at rest and under rigid motions,
  // so those stay exact). An edge's term (scaled target minus rest edge) is shared by the rows at
  // its two ends with opposite signs (exactly), so it is computed once per face: edge_terms()
  // gives face f's terms for its edges (c0 c1), (c0 c2), (c1 c2) in corner order, and rotated()
  // sums each row's from them.
  using EdgeTerms = std::array<Eigen::Vector3d, 3>;
  EdgeTerms edge_terms(int face, const Eigen::Matrix3d& mean, const double* rest, const double* x,
                       const OneSided& one_sided) const;
  Eigen::Vector3d rotated(int i, const std::vector<EdgeTerms>& terms) const;

  // The distinct faces of the fans (each is in up to three rows' fans), and face f's mean of
  // its corners' rot: rotated() takes these means, one per face (computed once, not per row).
  int n_faces() const { return static_cast<int>(corners_.size()); }
  const std::array<int, 3>& corners(int face) const { return corners_[static_cast<std::size_t>(face)]; }
  Eigen::Matrix3d mean(int face, const std::vector<Eigen::Matrix3d>& rot) const;

  // The membrane target's scale for an edge stretched by `stretch` along its target (the
  // projection that minimizes |e - s M r|, 1 for an unchanged edge): by default a compressed
  // edge is pushed out beyond its rest length, a stretched one is pulled back only halfway;
  // both bounded (docs/nonlinear.md, "What the gallery found", 21 and 28); grown faces: OneSided::grown.
  static double target_scale(double stretch, const OneSided& one_sided = {});

  // How much of the rotation field's change over face f turns about axes across its edges
  // (bending) rather than along them (twisting), in [0, 1]: 0 where the field does not change.
  // q: per local row, the field's rotations (their relative turn is taken in the rest frame).
  double bend_fraction(int face, const std::vector<Eigen::Quaterniond>& q, const double* rest) const;
  // one_sided with its stretch share raised toward bent_stretch_share on a face that bends
  // (from a bend_fraction of 0.5, fully from 0.8), where it bends clearly more than it twists: the
  // outside of a bent limb may stretch, so that its crook folds less; a twisted one keeps the
  // share, since releasing the stretch of a twist lets it gather in one place (docs/nonlinear.md,
  // "What the gallery found", 48).
  static OneSided where_bent(const OneSided& one_sided, double bend_fraction);

 private:
  struct Face {
    int j, n;       // the other corners, counter-clockwise from i
    int face;       // index into corners_
    int corner;     // i's place among the face's corners (j and n follow it cyclically)
    double wj, wn;  // lap's weight of edges (i, j) and (i, n) carried by this face
  };
  struct Spoke {
    int a;              // a ring vertex of the row
    Eigen::Vector3d g;  // sum over the fan's edges (a, b) of w_ab (r_a - r_b)
  };
  // Adds w (r_a - r_b) to the spoke of ring vertex a of row i (the row being built).
  void add_spoke(int i, int a, int b, double w, const double* rest);

  std::vector<int> offset_, spoke_offset_;
  std::vector<Face> faces_;
  std::vector<std::array<int, 3>> corners_;  // per distinct face: its local rows
  std::vector<Spoke> spokes_;
};

}  // namespace freeform
