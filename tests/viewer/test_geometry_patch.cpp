// GeometryPatch (viewer/geometry_patch.h): updating only the moving part of a scene gives the
// same floats as the whole-mesh recomputation (update_geometry), bit for bit, and touches
// nothing else.
#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"
#include "viewer/geometry_patch.h"
#include "viewer/region_colors.h"
#include "viewer/render_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace freeform;
using namespace freeform::viewer;

TEST(GeometryPatch, EqualsTheWholeMeshUpdateBitForBit) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(30, 30, 0.05, 2.0));
  RenderScene full = make_scene(mesh, kPlainColor);
  RenderScene patched = full;
  // Moving: a disk and a scattered few (non-contiguous indices), as an edit's support is.
  std::vector<Vertex> moving;
  for (Vertex v : mesh.vertices())
    if ((mesh.position(v) - Vec3(0.4, 0.6, 0)).norm() < 0.2 || v.idx() % 97 == 5) moving.push_back(v);
  const GeometryPatch patch(patched, moving);
  ASSERT_FALSE(patch.empty());
  EXPECT_LE(patch.ranges().size(), static_cast<std::size_t>(GeometryPatch::kMaxRanges));
  EXPECT_LT(patch.range_vertices(), mesh.n_vertices());
  for (int frame = 1; frame <= 3; ++frame) {
    VertexData<Vec3> p = mesh.positions();
    for (Vertex v : moving) p[v] += Vec3(0.01 * frame, std::sin(v.idx() * 0.1) * 0.02, 0.3 * frame);
    update_geometry(full, p);
    patch.apply(patched, p);
    EXPECT_EQ(patched.positions, full.positions) << "frame " << frame;
    EXPECT_EQ(patched.normals, full.normals) << "frame " << frame;
    EXPECT_EQ(patched.bounds.min, full.bounds.min);
    EXPECT_EQ(patched.bounds.max, full.bounds.max);
  }
  // Every vertex whose normal changed lies in the upload ranges.
  const RenderScene rest = make_scene(mesh, kPlainColor);
  std::vector<char> covered(static_cast<std::size_t>(mesh.n_vertices()), 0);
  for (const auto& [first, count] : patch.ranges())
    for (int v = first; v < first + count; ++v) covered[static_cast<std::size_t>(v)] = 1;
  for (int v = 0; v < mesh.n_vertices(); ++v)
    for (int k = 0; k < 3; ++k) {
      if (patched.normals[static_cast<std::size_t>(3 * v + k)] != rest.normals[static_cast<std::size_t>(3 * v + k)]) {
        ASSERT_TRUE(covered[static_cast<std::size_t>(v)]) << "vertex " << v << " changed outside the ranges";
      }
    }
}

TEST(GeometryPatch, RefusesWhatItWasNotBuiltFor) {
  const Mesh mesh = Mesh::from_soup(make_plane(4, 4));
  RenderScene scene = make_scene(mesh, kPlainColor);
  EXPECT_THROW(GeometryPatch(scene, std::vector<Vertex>{Vertex(999)}), InvalidInput);
  const GeometryPatch patch(scene, std::vector<Vertex>{Vertex(3)});
  EXPECT_THROW(patch.apply(scene, VertexData<Vec3>(2, Vec3::Zero())), InvalidInput);
  EXPECT_TRUE(GeometryPatch(scene, std::vector<Vertex>{}).empty());
}
