// What the renderer draws, GL-free: flat float arrays ready for upload. The editor updates
// `positions`/`normals` per frame in the deformed part only (geometry_patch.h) and keeps
// triangles and colours.
#pragma once

#include "viewer/camera.h"

#include "freeform/mesh/mesh.h"
#include "freeform/mesh/types.h"

#include <Eigen/Core>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

namespace freeform::viewer {

using Rgb = std::array<float, 3>;  // linear 0..1

struct RenderScene {
  std::vector<float> positions;         // #V x 3, xyz per vertex
  std::vector<float> normals;           // #V x 3, unit area-weighted vertex normals
  std::vector<float> colors;            // #V x 3, rgb per vertex
  std::vector<std::uint32_t> triangles; // #F x 3, counter-clockwise
  BoundingBox bounds;                   // of the positions
  // Scene coordinates are (mesh - origin) * scale: recentred scenes keep float precision far
  // from the origin (5e6) and beyond float's range (1e39). Identity unless make_scene recentres.
  Vec3 origin = Vec3::Zero();
  double scale = 1.0;
  Vec3 to_scene(const Vec3& p) const { return (p - origin) * scale; }
  Vec3 to_mesh(const Vec3& p) const { return origin + p / scale; }

  int n_vertices() const { return static_cast<int>(positions.size() / 3); }
  int n_triangles() const { return static_cast<int>(triangles.size() / 3); }
};

// The scene of a triangle soup in one colour. Vertices that no face uses get a zero normal.
// recentre: origin = the bounding box centre, scale = a power of two bringing its size near 1.
// Throws InvalidInput for an empty soup or a face index out of range.
RenderScene make_scene(const TriangleSoup& soup, const Rgb& color, bool recentre = false);
RenderScene make_scene(const Mesh& mesh, const Rgb& color, bool recentre = false);

// Replaces positions (mesh coordinates, mapped with the scene's origin and scale), recomputes
// normals and bounds (same vertex count; InvalidInput if not).
void update_geometry(RenderScene& scene, const VertexData<Vec3>& positions);

// Sets every vertex colour; `colors` has one entry per vertex (InvalidInput if not).
void set_colors(RenderScene& scene, const std::vector<Rgb>& colors);

BoundingBox bounding_box(const std::vector<float>& positions);
BoundingBox empty_box();                        // min +inf, max -inf: extend() fills it
void extend(BoundingBox& box, const float* p);  // by the point p[0..2]

// The pieces of the normal computation, shared with GeometryPatch so that both give the same
// floats: the area-weighted normal of triangle tri[0..2] of `positions`, accumulation, and
// normalization (a zero vector stays zero).
inline Eigen::Vector3f triangle_normal(const float* positions, const std::uint32_t* tri) {
  const float *a = positions + 3 * tri[0], *b = positions + 3 * tri[1], *c = positions + 3 * tri[2];
  const Eigen::Vector3f pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pc(c[0], c[1], c[2]);
  return (pb - pa).cross(pc - pa);  // length = 2 * area: area weighting
}
inline void add3(float* out, const Eigen::Vector3f& n) {
  for (int k = 0; k < 3; ++k) out[k] += n[k];
}
inline void normalize3(float* n) {
  const float len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (len > 0.0f)
    for (int k = 0; k < 3; ++k) n[k] /= len;
}

}  // namespace freeform::viewer
