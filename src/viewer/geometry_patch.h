// The part of a RenderScene that a deformation can change, so the editor's per-frame display
// update costs O(support), not O(mesh): given the vertices that move, apply() writes their
// positions, recomputes the normals of every vertex of a triangle they touch and the bounds
// (the precomputed box of the static vertices merged with the moving ones). Normals sum each
// vertex's triangles in triangle order with the same helpers as make_scene, so the result is
// bit for bit the full recomputation (update_geometry).
#pragma once

#include "viewer/render_scene.h"

#include <span>
#include <utility>
#include <vector>

namespace freeform::viewer {

class GeometryPatch {
 public:
  GeometryPatch() = default;
  // `moving`: vertex indices of the scene (any order, duplicates allowed). Cost O(#V + #F)
  // once. Throws InvalidInput for an index outside the scene.
  GeometryPatch(const RenderScene& scene, std::span<const Vertex> moving);

  // Writes the moving vertices' positions (#V entries, only those are read) and everything
  // that depends on them. Requires the scene the patch was built for (same counts).
  void apply(RenderScene& scene, const VertexData<Vec3>& positions) const;

  bool empty() const { return moving_.empty(); }
  // Vertex ranges (first, count) covering every vertex whose position or normal apply() may
  // change, ascending, at most kMaxRanges (nearby runs merged): the sub-buffers to upload.
  const std::vector<std::pair<int, int>>& ranges() const { return ranges_; }
  int range_vertices() const;  // the vertices those ranges cover
  static constexpr int kMaxRanges = 32;

 private:
  std::vector<std::uint32_t> moving_;
  std::vector<std::uint32_t> normal_vertices_;  // corners of the triangles a moving vertex touches
  std::vector<std::uint32_t> triangles_;        // the triangles around them (3 corners each), ascending
  std::vector<int> offset_, incident_;          // CSR: each normal vertex's triangles, ascending
  mutable std::vector<float> triangle_normal_;  // workspace: 3 per triangle of triangles_
  BoundingBox static_bounds_;                   // of the vertices that never move
  std::vector<std::pair<int, int>> ranges_;
  int n_vertices_ = 0, n_triangles_ = 0;
};

}  // namespace freeform::viewer
