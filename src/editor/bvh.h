// Bounding volume hierarchy over a mesh's triangles for CPU ray casts (picking and the
// visibility of painted vertices, no GL, testable without a window). A linear BVH: triangles sorted along a Morton
// curve (radix sort) and split at spatial medians into a flat node array, <= 2 triangles per
// leaf; refit() updates the boxes in O(n) after every deformation frame (same topology).
// (A binned-SAH build traced rays within ~10% of it but built 2-3x slower.)
#pragma once

#include "editor/screen.h"

#include "freeform/mesh/mesh.h"

#include <array>
#include <limits>
#include <optional>
#include <vector>

namespace freeform::editor {

struct RayHit {
  Face face;
  double t = 0.0;  // hit point = origin + t * direction (t is a distance for a unit direction)
  // Weights of mesh.vertices(face)[0..2] at the hit point (sum 1, each >= 0 up to rounding).
  Vec3 barycentric = Vec3::Zero();
};

class Bvh {
 public:
  Bvh() = default;  // empty: every ray misses
  // positions: the DISPLAYED positions, one per mesh vertex (may differ from mesh.positions()).
  // They are copied. Throws InvalidInput if the count does not match or one is not finite.
  // Cost O(F log F).
  Bvh(const Mesh& mesh, const VertexData<Vec3>& positions);

  // Closest hit with 0 < t < t_max (Möller–Trumbore in double precision; rays grazing a
  // triangle within ~1e-12 rad of its plane and degenerate triangles never hit). The direction
  // need not be unit length. Ties between faces at the same t go to either.
  std::optional<RayHit> intersect(const Ray& ray, double t_max = std::numeric_limits<double>::infinity()) const;

  // True if some triangle NOT incident to `ignore` is hit at 0 < t < t_max (any-hit query,
  // stops at the first). Pass an invalid vertex to ignore nothing.
  bool occluded(const Ray& ray, double t_max, Vertex ignore = Vertex()) const;

  // New positions for the same mesh (same vertex count): copies them and recomputes every box
  // bottom-up in O(V + nodes). The tree shape is kept, so after large deformations a rebuild
  // traverses faster (results are identical either way).
  void refit(const VertexData<Vec3>& positions);

  int n_faces() const { return static_cast<int>(tris_.size()); }
  int n_nodes() const { return static_cast<int>(nodes_.size()); }
  // Axis-aligned bounds of all triangles (zero box when empty).
  Vec3 bounds_min() const;
  Vec3 bounds_max() const;

 private:
  struct Node {
    double lo[3];
    double hi[3];
    int first;  // leaf: first triangle slot; interior: left child (the right child is first + 1)
    int count;  // leaf: number of triangles (> 0); interior: 0
  };
  template <class Visit>
  void traverse(const Ray& ray, double& t_max, Visit&& visit) const;
  void set_positions(const VertexData<Vec3>& positions);
  void refit_boxes();

  std::vector<Node> nodes_;
  std::vector<std::array<int, 3>> tris_;  // vertex indices per slot (leaf order)
  std::vector<int> face_;                 // mesh face of each slot
  std::vector<Vec3> pos_;                 // copy of the displayed positions
};

}  // namespace freeform::editor
