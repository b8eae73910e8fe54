#include "freeform/io/mesh_attributes.h"

#include <algorithm>

namespace freeform {

std::vector<double> recomputed_normals(const Polygons& polygons, const CornerAttribute& normal,
                                       std::span<const Vec3> positions, std::span<const Vec3> old_positions) {
  std::vector<double> out = normal.values;
  if (normal.empty() || normal.width != 3) return out;
  std::vector<Vec3> sum(static_cast<std::size_t>(normal.rows()), Vec3::Zero());
  std::vector<char> moved(sum.size(), old_positions.empty() ? 1 : 0);
  for (int p = 0; p < polygons.size(); ++p) {
    const int begin = polygons.offsets[static_cast<std::size_t>(p)];
    const int n = polygons.corner_count(p);
    bool polygon_moved = false;
    for (int i = 0; i < n && !old_positions.empty() && !polygon_moved; ++i) {
      const auto v = static_cast<std::size_t>(polygons.corners[static_cast<std::size_t>(begin + i)]);
      polygon_moved = positions[v] != old_positions[v];
    }
    // Newell's sum: twice the polygon's vector area, also for a non-planar polygon.
    Vec3 area = Vec3::Zero();
    for (int i = 0; i < n; ++i) {
      const Vec3& a = positions[static_cast<std::size_t>(polygons.corners[static_cast<std::size_t>(begin + i)])];
      const Vec3& b =
          positions[static_cast<std::size_t>(polygons.corners[static_cast<std::size_t>(begin + (i + 1) % n)])];
      area += a.cross(b);
    }
    for (int i = 0; i < n; ++i) {
      const int row = normal.index[static_cast<std::size_t>(begin + i)];
      if (row < 0) continue;
      sum[static_cast<std::size_t>(row)] += area;
      if (polygon_moved) moved[static_cast<std::size_t>(row)] = 1;
    }
  }
  for (std::size_t r = 0; r < sum.size(); ++r) {
    const double length = sum[r].norm();
    if (!moved[r] || !(length > 0)) continue;  // unused row or zero area: keep the file's value
    for (int c = 0; c < 3; ++c) out[r * 3 + static_cast<std::size_t>(c)] = sum[r][c] / length;
  }
  return out;
}

std::optional<std::vector<double>> per_vertex_values(const Polygons& polygons, const CornerAttribute& attribute,
                                                     int n_vertices) {
  const auto width = static_cast<std::size_t>(attribute.width);
  std::vector<double> out(static_cast<std::size_t>(n_vertices) * width, 0.0);
  std::vector<int> row_of(static_cast<std::size_t>(n_vertices), -1);
  for (std::size_t c = 0; c < polygons.corners.size(); ++c) {
    const int row = attribute.index[c];
    if (row < 0) return std::nullopt;  // a corner without a value
    const auto v = static_cast<std::size_t>(polygons.corners[c]);
    const double* value = attribute.values.data() + static_cast<std::size_t>(row) * width;
    if (row_of[v] < 0) {
      row_of[v] = row;
      std::copy(value, value + width, out.begin() + static_cast<std::ptrdiff_t>(v * width));
    } else if (row_of[v] != row && !std::equal(value, value + width, out.begin() + static_cast<std::ptrdiff_t>(v * width))) {
      return std::nullopt;
    }
  }
  return out;
}

void polygons_from_triangles(const TriangleSoup& soup, MeshAttributes& attributes) {
  attributes.polygons = {};
  attributes.polygons.corners.reserve(soup.faces.size() * 3);
  attributes.polygons.offsets.reserve(soup.faces.size() + 1);
  attributes.triangle_polygon.resize(soup.faces.size());
  for (std::size_t t = 0; t < soup.faces.size(); ++t) {
    attributes.polygons.add(soup.faces[t]);
    attributes.triangle_polygon[t] = static_cast<int>(t);
  }
}

}  // namespace freeform
