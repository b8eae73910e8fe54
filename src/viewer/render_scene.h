// What the renderer draws, GL-free: flat float arrays ready for upload. The editor rebuilds
// `positions`/`normals` per frame (update_geometry) and keeps triangles and colours.
#pragma once

#include "viewer/camera.h"

#include "freeform/mesh/mesh.h"
#include "freeform/mesh/types.h"

#include <array>
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

  int n_vertices() const { return static_cast<int>(positions.size() / 3); }
  int n_triangles() const { return static_cast<int>(triangles.size() / 3); }
};

// The scene of a triangle soup in one colour. Vertices that no face uses get a zero normal.
// Throws InvalidInput for an empty soup or a face index out of range.
RenderScene make_scene(const TriangleSoup& soup, const Rgb& color);
RenderScene make_scene(const Mesh& mesh, const Rgb& color);

// Replaces positions, recomputes normals and bounds (same vertex count; InvalidInput if not).
void update_geometry(RenderScene& scene, const VertexData<Vec3>& positions);

// Sets every vertex colour; `colors` has one entry per vertex (InvalidInput if not).
void set_colors(RenderScene& scene, const std::vector<Rgb>& colors);

BoundingBox bounding_box(const std::vector<float>& positions);

}  // namespace freeform::viewer
