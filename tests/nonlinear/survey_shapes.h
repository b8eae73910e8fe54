// Survey-like shapes, edits and measurements of the nonlinear issue (Botsch & Sorkine's
// deformation survey, rebuilt from its description): a closed square bar, a closed capsule
// ("cylinder"), libcgal-demo's cactus with their edits, and per-face quality measures
// computed here from the face list.
#pragma once

#include "freeform/edit/edit.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/types.h"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <map>
#include <numbers>
#include <tuple>
#include <vector>

namespace freeform::test {

// Closed box [0,sx] x [0,sy] x [0,sz], n cells per unit length, outward faces.
inline TriangleSoup make_box(double sx, double sy, double sz, int per_unit) {
  TriangleSoup soup;
  std::map<std::tuple<long, long, long>, int> index;
  auto vertex = [&](const Vec3& p) {
    const auto key = std::make_tuple(std::lround(p.x() * 1e6), std::lround(p.y() * 1e6), std::lround(p.z() * 1e6));
    auto [it, added] = index.emplace(key, static_cast<int>(soup.positions.size()));
    if (added) soup.positions.push_back(p);
    return it->second;
  };
  const Vec3 size(sx, sy, sz);
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // e_a x e_b = e_axis
      const int na = std::max(1, static_cast<int>(std::lround(size[a] * per_unit)));
      const int nb = std::max(1, static_cast<int>(std::lround(size[b] * per_unit)));
      std::vector<int> ids;
      for (int j = 0; j <= nb; ++j)
        for (int i = 0; i <= na; ++i) {
          Vec3 p = Vec3::Zero();
          p[axis] = side * size[axis];
          p[a] = size[a] * i / na;
          p[b] = size[b] * j / nb;
          ids.push_back(vertex(p));
        }
      for (int j = 0; j < nb; ++j)
        for (int i = 0; i < na; ++i) {
          const int v00 = ids[j * (na + 1) + i], v10 = ids[j * (na + 1) + i + 1];
          const int v01 = ids[(j + 1) * (na + 1) + i], v11 = ids[(j + 1) * (na + 1) + i + 1];
          if (side == 1) {
            soup.faces.push_back({v00, v10, v11});
            soup.faces.push_back({v00, v11, v01});
          } else {
            soup.faces.push_back({v00, v11, v10});
            soup.faces.push_back({v00, v01, v11});
          }
        }
    }
  return soup;
}

// Closed surface of revolution about the z axis: `circles` (z, radius) from bottom to top, each
// with `segments` vertices, closed by a pole vertex below the first and above the last.
inline TriangleSoup make_lathe(const std::vector<std::pair<double, double>>& circles, double bottom, double top,
                               int segments) {
  TriangleSoup soup;
  soup.positions.push_back(Vec3(0, 0, bottom));
  for (const auto& [z, r] : circles)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * std::numbers::pi * s / segments;
      soup.positions.push_back(Vec3(r * std::cos(a), r * std::sin(a), z));
    }
  soup.positions.push_back(Vec3(0, 0, top));
  const int n_circles = static_cast<int>(circles.size()), last = static_cast<int>(soup.positions.size()) - 1;
  auto id = [&](int c, int s) { return 1 + c * segments + (s % segments); };
  for (int s = 0; s < segments; ++s) soup.faces.push_back({0, id(0, s + 1), id(0, s)});
  for (int c = 0; c + 1 < n_circles; ++c)
    for (int s = 0; s < segments; ++s) {
      soup.faces.push_back({id(c, s), id(c, s + 1), id(c + 1, s + 1)});
      soup.faces.push_back({id(c, s), id(c + 1, s + 1), id(c + 1, s)});
    }
  for (int s = 0; s < segments; ++s) soup.faces.push_back({last, id(n_circles - 1, s), id(n_circles - 1, s + 1)});
  return soup;
}

// Closed capsule around the z axis: a tube of the given radius for z in [0, length] with
// hemispherical caps, `segments` around, `rings` along the tube, segments / 4 per cap.
inline TriangleSoup make_capsule(double radius, double length, int segments, int rings) {
  const int cap = segments / 4;
  std::vector<std::pair<double, double>> circles;  // (z, r) from bottom to top
  for (int k = cap - 1; k >= 1; --k) {
    const double t = std::numbers::pi / 2 * k / cap;
    circles.emplace_back(-radius * std::sin(t), radius * std::cos(t));
  }
  for (int k = 0; k <= rings; ++k) circles.emplace_back(length * k / rings, radius);
  for (int k = 1; k < cap; ++k) {
    const double t = std::numbers::pi / 2 * k / cap;
    circles.emplace_back(length + radius * std::sin(t), radius * std::cos(t));
  }
  return make_lathe(circles, -radius, length + radius, segments);
}

// Closed cylinder with flat caps, z in [0, length]: `rings` along the tube, `cap_rings`
// concentric circles per cap (the pole included).
inline TriangleSoup make_flat_cylinder(double radius, double length, int segments, int rings, int cap_rings) {
  std::vector<std::pair<double, double>> circles;
  for (int k = 1; k < cap_rings; ++k) circles.emplace_back(0.0, radius * k / cap_rings);
  for (int k = 0; k <= rings; ++k) circles.emplace_back(length * k / rings, radius);
  for (int k = cap_rings - 1; k >= 1; --k) circles.emplace_back(length, radius * k / cap_rings);
  return make_lathe(circles, 0.0, length, segments);
}

// Enclosed volume (divergence theorem; positive for outward faces) of the faces [first, last)
// (last < 0: all of them; a range: one closed component whose faces are contiguous).
inline double volume(const Mesh& mesh, const VertexData<Vec3>& p, int first = 0, int last = -1) {
  double v = 0;
  for (int f = first; f < (last < 0 ? mesh.n_faces() : last); ++f) {
    const auto c = mesh.vertices(Face(f));
    v += p[c[0]].dot(p[c[1]].cross(p[c[2]])) / 6.0;
  }
  return v;
}

// Singular values (largest first) of face f's deformation gradient (rest triangle -> deformed):
// both 1 for rigid motions; their product is the face's area ratio.
inline Eigen::Vector2d face_singular_values(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<Vec3>& p,
                                            Face f) {
  const auto c = mesh.vertices(f);
  const Vec3 e1 = rest[c[1]] - rest[c[0]], e2 = rest[c[2]] - rest[c[0]];
  const Vec3 u = e1.normalized(), w = (e2 - e2.dot(u) * u).normalized();
  Eigen::Matrix2d r;
  r << e1.dot(u), e2.dot(u), e1.dot(w), e2.dot(w);
  Eigen::Matrix<double, 3, 2> d;
  d << p[c[1]] - p[c[0]], p[c[2]] - p[c[0]];
  const Eigen::Matrix<double, 3, 2> j = d * r.inverse();
  return Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>>(j).singularValues();
}

// The smallest of them, the collapse measure: < 1 where the face shrinks in some direction.
inline double face_min_singular_value(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<Vec3>& p,
                                      Face f) {
  return face_singular_values(mesh, rest, p, f)[1];
}

// The smallest over all faces.
inline double min_singular_value(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<Vec3>& p) {
  double lo = std::numeric_limits<double>::infinity();
  for (Face f : mesh.faces()) lo = std::min(lo, face_min_singular_value(mesh, rest, p, f));
  return lo;
}

// The survey set-ups (support = every vertex not fixed, one handle with its transform), shared
// by tests/nonlinear and bench/bench_nonlinear.cpp.
struct Shape {
  std::string name;
  Mesh mesh;
  Edit edit;
};


// Support: every vertex not fixed; handle: vertices with `is_handle`.
inline Shape setup(std::string name, const TriangleSoup& soup, const std::function<bool(const Vec3&)>& is_fixed,
            const std::function<bool(const Vec3&)>& is_handle, const Eigen::Affine3d& t) {
  Shape s{std::move(name), Mesh::from_soup(soup), {}};
  EditHandle h;
  for (Vertex v : s.mesh.vertices()) {
    const Vec3& p = s.mesh.position(v);
    if (!is_fixed(p)) s.edit.support.push_back(v);
    if (is_handle(p)) h.vertices.push_back(v);
  }
  h.matrix = t;
  s.edit.handles.push_back(h);
  s.edit.multiresolution = false;
  return s;
}

inline Eigen::Affine3d rotation_about(const Vec3& pivot, double degrees, const Vec3& axis) {
  return Eigen::Translation3d(pivot) * Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()) *
         Eigen::Translation3d(-pivot);
}

inline Shape bar_twist() {
  return setup("bar", make_box(1, 1, 5, 10), [](const Vec3& p) { return p.z() < 0.5; },
               [](const Vec3& p) { return p.z() > 4.5; }, rotation_about(Vec3(0.5, 0.5, 0), 135, Vec3::UnitZ()));
}

// The free part (z in [1, 7]) bent into a circular arc of 120 degrees: the handle's base circle
// goes to the arc's end, turned by 120 degrees about y.
inline Shape cylinder_bend() {
  const double theta = 120.0 * std::numbers::pi / 180.0, rho = 6.0 / theta;
  const Vec3 arc_end(rho - rho * std::cos(theta), 0.0, 1.0 + rho * std::sin(theta));
  const Eigen::Affine3d t =
      Eigen::Translation3d(arc_end) * Eigen::AngleAxisd(theta, Vec3::UnitY()) * Eigen::Translation3d(Vec3(0, 0, -7.0));
  return setup("cylinder", make_capsule(1.0, 8.0, 32, 64), [](const Vec3& p) { return p.z() < 1.0; },
               [](const Vec3& p) { return p.z() > 7.0; }, t);
}

// The deformation survey's cylinder test with flat caps (radius 1, length 12, 4,658 vertices):
// the bottom 0.5 fixed, the top 0.5 the handle, turned 120 degrees about an axis across the tube
// through its middle. Multiresolution is left on: the membrane fill of a long tube pinches
// toward its axis, so the decomposition's "detail" is the whole radius.
inline Shape flat_cylinder_bend() {
  Shape s = setup("flat-cylinder", make_flat_cylinder(1.0, 12.0, 48, 90, 4), [](const Vec3& p) { return p.z() < 0.5; },
                  [](const Vec3& p) { return p.z() > 11.5; }, rotation_about(Vec3(0, 0, 6), 120, Vec3::UnitY()));
  s.edit.multiresolution = true;
  return s;
}

// libcgal-demo's cactus (y up): the right arm, from where it leaves the trunk, bent 70 degrees
// outward about its elbow; the arm's tip is the handle.
inline std::optional<Shape> cactus_bend(const std::filesystem::path& mesh_dir) {
  const std::filesystem::path file = mesh_dir / "cactus.off";
  if (!std::filesystem::exists(file)) return std::nullopt;
  return setup("cactus", read_mesh(file.string()).soup, [](const Vec3& p) { return p.x() < 0.1; },
               [](const Vec3& p) { return p.x() > 0.2 && p.y() > 0.38; },
               rotation_about(Vec3(0.3, 0.2, 0.0), -70, Vec3::UnitZ()));
}

// libcgal-demo's cactus, bent as a whole: the bottom fixed, the top of the trunk the handle,
// the trunk and both arms in the support, the handle turned 70 degrees sideways about the
// trunk's foot. `subdivisions` midpoint subdivisions (0: the file's 620 vertices).
inline std::optional<Shape> cactus_whole_bend(const std::filesystem::path& mesh_dir, int subdivisions = 1) {
  const std::filesystem::path file = mesh_dir / "cactus.off";
  if (!std::filesystem::exists(file)) return std::nullopt;
  TriangleSoup soup = read_mesh(file.string()).soup;
  for (int i = 0; i < subdivisions; ++i) soup = subdivide_midpoint(soup);
  Shape s = setup("cactus-whole", soup, [](const Vec3& p) { return p.y() < -0.63; },
                  [](const Vec3& p) { return p.y() > 0.42 && p.x() > -0.15 && p.x() < 0.1; },
                  rotation_about(Vec3(-0.025, -0.63, 0.0), -70, Vec3::UnitZ()));
  s.edit.multiresolution = true;
  return s;
}

}  // namespace freeform::test
