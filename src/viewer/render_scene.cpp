#include "viewer/render_scene.h"

#include "freeform/common/error.h"

#include <cmath>
#include <limits>

namespace freeform::viewer {
namespace {

void compute_normals(RenderScene& s) {
  s.normals.assign(s.positions.size(), 0.0f);
  const float* p = s.positions.data();
  for (std::size_t t = 0; t + 2 < s.triangles.size(); t += 3) {
    const std::uint32_t a = s.triangles[t], b = s.triangles[t + 1], c = s.triangles[t + 2];
    const Eigen::Vector3f pa(p[3 * a], p[3 * a + 1], p[3 * a + 2]), pb(p[3 * b], p[3 * b + 1], p[3 * b + 2]),
        pc(p[3 * c], p[3 * c + 1], p[3 * c + 2]);
    const Eigen::Vector3f n = (pb - pa).cross(pc - pa);  // length = 2 * area: area weighting
    for (const std::uint32_t v : {a, b, c})
      for (int k = 0; k < 3; ++k) s.normals[3 * v + k] += n[k];
  }
  for (std::size_t v = 0; v + 2 < s.normals.size(); v += 3) {
    const float len = std::sqrt(s.normals[v] * s.normals[v] + s.normals[v + 1] * s.normals[v + 1] +
                                s.normals[v + 2] * s.normals[v + 2]);
    if (len > 0.0f)
      for (int k = 0; k < 3; ++k) s.normals[v + k] /= len;
  }
}

}  // namespace

BoundingBox bounding_box(const std::vector<float>& positions) {
  BoundingBox b;
  if (positions.empty()) return b;
  b.min = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  b.max = -b.min;
  for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
    const Eigen::Vector3d q(positions[i], positions[i + 1], positions[i + 2]);
    b.min = b.min.cwiseMin(q);
    b.max = b.max.cwiseMax(q);
  }
  return b;
}

RenderScene make_scene(const TriangleSoup& soup, const Rgb& color) {
  if (soup.positions.empty() || soup.faces.empty()) throw InvalidInput("nothing to render: the mesh has no triangles");
  RenderScene s;
  const std::size_t n = soup.positions.size();
  s.positions.reserve(3 * n);
  for (const Vec3& q : soup.positions) {
    if (!q.allFinite()) throw InvalidInput("cannot render a mesh with non-finite positions");
    for (int k = 0; k < 3; ++k) s.positions.push_back(static_cast<float>(q[k]));
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

RenderScene make_scene(const Mesh& mesh, const Rgb& color) { return make_scene(mesh.to_soup(), color); }

void update_geometry(RenderScene& scene, const VertexData<Vec3>& positions) {
  if (static_cast<int>(positions.size()) != scene.n_vertices())
    throw InvalidInput("update_geometry: vertex count changed");
  for (int v = 0; v < scene.n_vertices(); ++v) {
    const Vec3& q = positions[Vertex(v)];
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
