// The enclosed volume of each closed component the nonlinear model deforms (docs/nonlinear.md):
// rotation-aware models keep edge lengths, so a twisted bar necks (ARAP keeps 0.72 of its
// volume); the model adds lambda * u, u the smooth response of its own operator to the volume
// gradient, with lambda chosen so that the volume is the target: the rest volume, or where the
// handles are dragged (not only turned) or scaled, the volume of the rest moved by those drags
// and scalings alone (a limb pushed in loses what it must, one pulled out keeps its thickness,
// one whose end is shrunk tapers).
#pragma once

#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <span>
#include <vector>

namespace freeform {

class EnclosedVolumes {
 public:
  using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  // local[v]: v's row among the model's vertices (free rows first, n_free of them), or -1.
  // Keeps the closed components (no boundary edge) with a free vertex. part_of_row (optional):
  // the support part of each row (its first rows; support_parts(), part_settings.h): each closed
  // component keeps one volume per support part in it (parts that share a handle together), in
  // which the other parts' free vertices and handles stay at rest, so that every part restores
  // what its own deformation changed (as when edited alone) and does not inflate the others.
  EnclosedVolumes(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<int>& local, int n_free,
                  const Regions& regions, std::span<const int> part_of_row = {});

  // The volumes kept: per closed component with free vertices, one per support part (or parts
  // sharing a handle) in it.
  int count() const { return static_cast<int>(parts_.size()); }

  // For one frame: places the vertices the model does not hold (handle interiors, fixed
  // parts), sums the faces without a free corner at x (its constrained rows: this frame's) and
  // sets the targets. dragged (optional): the rest moved by the handles' drags and scalings
  // (every local row), moves[m] handle m's (its vertices without a row move by it); the targets
  // are then that shape's volumes instead of the rest's. Until the next start, volume(),
  // gradient() and multiplier() take positions whose constrained rows are those of x.
  void start(std::span<const Eigen::Affine3d> transforms, const RowMatrixX3d& x, const RowMatrixX3d* dragged = nullptr,
             std::span<const Eigen::Affine3d> moves = {});

  // Volumes and gradients are computed on the component's positions centred and scaled by a
  // power of two (exact), so that they neither overflow nor underflow at any size:
  // scale(c) ~ the component's rest extent.
  double scale(int c) const { return parts_[static_cast<std::size_t>(c)].scale; }
  // Gradient of component c's volume at x (local rows) in the free rows of g, other rows 0,
  // divided by scale(c)^2.
  void gradient(int c, const RowMatrixX3d& x, Eigen::Ref<Eigen::MatrixXd> g) const;
  // Volume of component c at x divided by scale(c)^3.
  double volume(int c, const RowMatrixX3d& x) const;
  // The lambda nearest to 0 for which component c's volume at x + lambda u (u: free rows) is
  // the target (a root of that cubic); 0 if no root moves a vertex by less than the
  // component's extent and 16 times the even offset of the moving faces that restores the
  // volume (a larger move stretches thin parts instead of inflating the component).
  double multiplier(int c, const RowMatrixX3d& x, const Eigen::MatrixXd& u) const;

 private:
  struct Part {
    // Corners: >= 0 a local row, < 0 the extra vertex -1 - i. Moving: a face with a free
    // corner; the others' volume is summed once per frame (fixed_sum, 6 times their volume).
    std::vector<std::array<int, 3>> moving, fixed;
    double fixed_sum = 0;
    // Per free row of the component (free_rows), the other two corners of each of its moving
    // faces, in the order of the face's cross product (2 per face, in face order), from
    // 2 * corner_offset[i] to 2 * corner_offset[i + 1]: the gradient's gather.
    std::vector<int> free_rows, corner_offset, opposite;
    std::vector<Vertex> extra;     // component vertices without a local row
    std::vector<int> extra_owner;  // their movable handle, or -1
    std::vector<Vec3> extra_rest, extra_now;
    std::vector<Vec3> extra_scaled;      // extra_now centred and scaled as corner() does
    std::vector<int> local_rows;         // the component's local rows
    Vec3 centre = Vec3::Zero();          // of the rest, for accuracy far from the origin
    double scale = 1, inv_scale = 1;     // a power of two near the rest extent, and its inverse
    double rest_volume = 0, target = 0;  // divided by scale^3
  };
  std::vector<Part> parts_;
  int n_free_ = 0;
  // Workspace of gradient() and multiplier() (per local row: scale_corners(), and u scaled the
  // same way): one caller at a time, like the solver that owns this.
  mutable std::vector<Vec3> scaled_, scaled_u_;

  struct Roles;
  void add_part(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<int>& local, const Roles& roles,
                int group, const std::vector<Vertex>& vertices, const std::vector<Face>& faces,
                VertexData<int>& extra_index);

  Vec3 corner(const Part& part, int index, const RowMatrixX3d& x) const;
  // The part's local rows at x centred and scaled into scaled_ (corner()'s bits; the extra
  // vertices' are extra_scaled, set by scale_extras() with extra_now): a face sum then scales
  // each vertex once, not once per face.
  void scale_corners(const Part& part, const RowMatrixX3d& x) const;
  const Vec3& scaled(const Part& part, int index) const {
    return index >= 0 ? scaled_[static_cast<std::size_t>(index)]
                      : part.extra_scaled[static_cast<std::size_t>(-1 - index)];
  }
  static void scale_extras(Part& part);
  void index_free_corners(Part& part) const;
  double fixed_sum(const Part& part, const RowMatrixX3d& x) const;
  double moving_sum(const Part& part, const RowMatrixX3d& x) const;
};

}  // namespace freeform
