// Screen-space picking of the displayed surface (GL-free, testable without a window): the vertices under a
// brush circle or inside a lasso, and the surface point under the cursor. Only visible
// vertices are selected; visibility is decided by CPU ray casts against a Bvh.
//
// Visibility: vertex v (displayed position p) is visible iff
//   - it has at least one incident face (isolated vertices are not on the surface),
//   - it is in front of the eye (clip w > 0) and its projection lies inside the viewport
//     [0, width] x [0, height] (the near/far planes are not considered),
//   - the segment eye -> p hits no triangle that is not incident to v at a distance
//     t < (1 - 1e-6) |p - eye| - 1e-7 * (bounding-box diagonal).
// Incident triangles are ignored because they all touch p; the tolerances keep vertices on a
// flat or convex surface, and coincident seam copies of a vertex, visible despite rounding.
#pragma once

#include "editor/bvh.h"
#include "editor/screen.h"

#include "freeform/mesh/mesh.h"

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace freeform::editor {

struct SurfacePick {
  Face face;
  Vec3 point = Vec3::Zero();               // world position of the hit (displayed geometry)
  Vec3 barycentric = Vec3::Zero();         // weights of mesh.vertices(face) at the hit
  double distance = 0.0;                   // from the eye
  Vertex vertex;                           // the vertex of `face` nearest to `point`
};

// Answers picking queries for one camera and one geometry state. Construction projects every
// vertex once (O(V)); visibility is ray cast on demand and cached, so a brush stroke over the
// same view casts each ray at most once. Make a new picker when the camera, the viewport or
// the positions change. Holds references to mesh, positions and bvh (they must outlive it and
// bvh must be built or refitted for these positions). Not thread-safe (the cache is mutable).
class ScreenPicker {
 public:
  ScreenPicker(const Mesh& mesh, const VertexData<Vec3>& positions, const Bvh& bvh, const ScreenView& view);

  // Visible vertices whose projection is within radius_px of center_px; sorted, unique.
  std::vector<Vertex> brush(const Eigen::Vector2d& center_px, double radius_px) const;
  // Visible vertices whose projection is inside the closed polygon (even-odd rule; the last
  // point connects to the first); sorted, unique. Fewer than 3 points select nothing.
  std::vector<Vertex> lasso(std::span<const Eigen::Vector2d> polygon_px) const;
  // The first surface hit along the ray through the pixel; nullopt on background or outside
  // the viewport.
  std::optional<SurfacePick> pick(const Eigen::Vector2d& px) const;

  bool visible(Vertex v) const;
  // Pixel position of v (possibly outside the viewport); nullopt if v is behind the eye or isolated.
  std::optional<Eigen::Vector2d> pixel(Vertex v) const;
  const ScreenView& view() const { return view_; }

 private:
  bool on_screen(int i) const;  // in front of the eye, inside the viewport, not isolated
  // Keeps the visible ones of candidate vertices (ascending), casting uncached rays.
  std::vector<Vertex> keep_visible(const std::vector<int>& candidates) const;
  bool cast(int i) const;

  const Mesh& mesh_;
  const VertexData<Vec3>& positions_;
  const Bvh& bvh_;
  ScreenView view_;
  double abs_tol_ = 0.0;
  std::vector<Eigen::Vector2d> px_;
  std::vector<std::uint8_t> front_;  // 1: in front of the eye and not isolated
  mutable std::vector<std::uint8_t> vis_;  // 0 unknown, 1 visible, 2 hidden
};

}  // namespace freeform::editor
