#include "viewer/render_scene.h"

#include "freeform/common/error.h"

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

namespace freeform::viewer {
namespace {

void compute_normals(RenderScene& s) {
  s.normals.assign(s.positions.size(), 0.0f);
  const float* p = s.positions.data();
  for (std::size_t t = 0; t + 2 < s.triangles.size(); t += 3) {
    const Eigen::Vector3f n = triangle_normal(p, &s.triangles[t]);
    for (std::size_t k = 0; k < 3; ++k) add3(&s.normals[3 * s.triangles[t + k]], n);
  }
  for (std::size_t v = 0; v + 2 < s.normals.size(); v += 3) normalize3(&s.normals[v]);
}

}  // namespace

BoundingBox bounding_box(const std::vector<float>& positions) {
  BoundingBox b;
  if (positions.empty()) return b;
  b = empty_box();
  for (std::size_t i = 0; i + 2 < positions.size(); i += 3) extend(b, &positions[i]);
  return b;
}

BoundingBox empty_box() {
  BoundingBox b;
  b.min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  b.max = -b.min;
  return b;
}

void extend(BoundingBox& box, const float* p) {
  const Eigen::Vector3d q(p[0], p[1], p[2]);
  box.min = box.min.cwiseMin(q);
  box.max = box.max.cwiseMax(q);
}

RenderScene make_scene(const TriangleSoup& soup, const Rgb& color, bool recentre) {
  if (soup.positions.empty() || soup.faces.empty()) throw InvalidInput("nothing to render: the mesh has no triangles");
  RenderScene s;
  const std::size_t n = soup.positions.size();
  Eigen::AlignedBox3d box;
  for (const Vec3& q : soup.positions) {
    if (!q.allFinite()) throw InvalidInput("cannot render a mesh with non-finite positions");
    box.extend(q);
  }
  if (recentre) {
    s.origin = box.min() + 0.5 * (box.max() - box.min());  // no overflow near +-1.8e308
    const double extent = (box.max() - box.min()).maxCoeff();
    if (extent > 0.0 && std::isfinite(extent)) s.scale = std::ldexp(1.0, -std::ilogb(extent));
  }
  s.positions.reserve(3 * n);
  for (const Vec3& q : soup.positions) {
    const Vec3 p = s.to_scene(q);
    for (int k = 0; k < 3; ++k) s.positions.push_back(static_cast<float>(p[k]));
  }
  s.triangles.reserve(3 * soup.faces.size());
  for (const Tri& f : soup.faces)
    for (const int v : f) {
      if (v < 0 || static_cast<std::size_t>(v) >= n) throw InvalidInput("cannot render: face index out of range");
      s.triangles.push_back(static_cast<std::uint32_t>(v));
    }
  s.colors.resize(3 * n);
  for (std::size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) s.colors[3 * v + k] = color[static_cast<std::size_t>(k)];
  compute_normals(s);
  s.bounds = bounding_box(s.positions);
  return s;
}

RenderScene make_scene(const Mesh& mesh, const Rgb& color, bool recentre) {
  return make_scene(mesh.to_soup(), color, recentre);
}

void update_geometry(RenderScene& scene, const VertexData<Vec3>& positions) {
  if (static_cast<int>(positions.size()) != scene.n_vertices())
    throw InvalidInput("update_geometry: vertex count changed");
  for (int v = 0; v < scene.n_vertices(); ++v) {
    const Vec3 q = scene.to_scene(positions[Vertex(v)]);
    for (int k = 0; k < 3; ++k) scene.positions[static_cast<std::size_t>(3 * v + k)] = static_cast<float>(q[k]);
  }
  compute_normals(scene);
  scene.bounds = bounding_box(scene.positions);
}

void set_colors(RenderScene& scene, const std::vector<Rgb>& colors) {
  if (static_cast<int>(colors.size()) != scene.n_vertices()) throw InvalidInput("set_colors: one colour per vertex expected");
  for (std::size_t v = 0; v < colors.size(); ++v)
    for (std::size_t k = 0; k < 3; ++k) scene.colors[3 * v + k] = colors[v][k];
}

}  // namespace freeform::viewer
