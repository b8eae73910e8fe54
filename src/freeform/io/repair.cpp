#include "freeform/io/repair.h"

#include "freeform/common/error.h"

#include <cstdint>
#include <unordered_map>

namespace freeform {
namespace {

// The rows (of `width` values) whose flag is set, in order.
std::vector<double> kept_rows(const std::vector<double>& values, int width, const std::vector<char>& keep) {
  std::vector<double> out;
  const auto w = static_cast<std::size_t>(width);
  for (std::size_t r = 0; r < keep.size() && (r + 1) * w <= values.size(); ++r)
    if (keep[r])
      out.insert(out.end(), values.begin() + static_cast<std::ptrdiff_t>(r * w),
                 values.begin() + static_cast<std::ptrdiff_t>((r + 1) * w));
  return out;
}

// Appends to each per-vertex attribute the rows of the vertices the repair copied.
void copy_vertex_rows(std::vector<NamedAttribute>& attributes, const std::vector<int>& origin) {
  for (NamedAttribute& a : attributes) {
    const auto w = static_cast<std::size_t>(a.width);
    for (int o : origin)
      for (std::size_t c = 0; c < w; ++c) {
        const double value = a.values.at(static_cast<std::size_t>(o) * w + c);
        a.values.push_back(value);
      }
  }
}

}  // namespace

MeshAttributes repaired_attributes(const MeshAttributes& in, const TriangleSoup& repaired, const BuildReport& report,
                                   int n_original) {
  MeshAttributes out = in;
  copy_vertex_rows(out.vertex, report.origin);
  const int n_polygons = in.polygons.size();
  out.triangle_polygon.assign(repaired.faces.size(), 0);
  if (n_polygons == 0) {
    out.triangle_polygon.clear();
    return out;
  }
  // Which polygons keep a triangle, and which copy of a split vertex their triangles use.
  std::vector<char> alive(static_cast<std::size_t>(n_polygons), 0);
  std::unordered_map<std::int64_t, int> renamed;  // polygon * n_original + vertex -> its copy
  for (std::size_t f = 0; f < repaired.faces.size(); ++f) {
    const auto t = static_cast<std::size_t>(report.face_origin.at(f));
    if (t >= in.triangle_polygon.size()) throw InternalError("repaired_attributes: a face has no polygon");
    const int p = in.triangle_polygon[t];
    out.triangle_polygon[f] = p;
    alive[static_cast<std::size_t>(p)] = 1;
    for (int w : repaired.faces[f])
      if (w >= n_original)
        renamed[std::int64_t{p} * n_original + report.origin[static_cast<std::size_t>(w - n_original)]] = w;
  }
  Polygons polygons;
  std::vector<int> new_index(static_cast<std::size_t>(n_polygons), -1), corners;
  std::vector<char> keep_corner;
  for (int p = 0; p < n_polygons; ++p) {
    const int begin = in.polygons.offsets[static_cast<std::size_t>(p)], n = in.polygons.corner_count(p);
    keep_corner.insert(keep_corner.end(), static_cast<std::size_t>(n), alive[static_cast<std::size_t>(p)]);
    if (!alive[static_cast<std::size_t>(p)]) continue;
    new_index[static_cast<std::size_t>(p)] = polygons.size();
    corners.clear();
    for (int j = 0; j < n; ++j) {
      const int v = in.polygons.corners[static_cast<std::size_t>(begin + j)];
      const auto it = renamed.find(std::int64_t{p} * n_original + v);
      corners.push_back(it == renamed.end() ? v : it->second);
    }
    polygons.add(corners);
  }
  out.polygons = std::move(polygons);
  for (int& p : out.triangle_polygon) p = new_index[static_cast<std::size_t>(p)];
  for (CornerAttribute* a : {&out.uv, &out.normal}) {
    if (a->empty()) continue;
    std::vector<int> index;
    for (std::size_t c = 0; c < keep_corner.size() && c < a->index.size(); ++c)
      if (keep_corner[c]) index.push_back(a->index[c]);
    a->index = std::move(index);
  }
  for (NamedAttribute& a : out.face) a.values = kept_rows(a.values, a.width, alive);
  return out;
}

Mesh manifold_mesh(const TriangleSoup& soup, const std::string& path) {
  try {
    return Mesh::from_soup(soup);
  } catch (const TopologyError& e) {
    throw TopologyError(
        path + ": " + e.what() + " (`freeform convert --repair " + path +
        " OUT` writes a repaired copy that keeps the file's polygons, texture coordinates and colours)");
  }
}

BuildReport repair(ReadResult& file, std::string& lost) {
  BuildReport report;
  TriangleSoup repaired = Mesh::from_soup(file.soup, BuildOptions{.repair = true}, &report).to_soup();
  lost.clear();
  if (!report.changed()) return report;
  file.attributes =
      repaired_attributes(file.attributes, repaired, report, static_cast<int>(file.soup.positions.size()));
  file.soup = std::move(repaired);
  if (file.source) lost = file.source->kept_only_by_rewrite();
  file.source.reset();
  return report;
}

}  // namespace freeform
