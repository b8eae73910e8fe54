#include "freeform/io/repair.h"

#include "freeform/common/error.h"

#include <cstdint>
#include <unordered_map>

namespace freeform {
namespace {

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

// A polygon of the repaired file: its corners (repaired vertices), and per corner the corner of
// the read polygon it comes from (an index into Polygons::corners, -1 none).
struct Emitted {
  int source = 0;
  std::vector<int> corners, from;
};

// The read polygons as the repaired triangles use them. A polygon stays whole, its corners
// renamed to the copies its triangles use, unless the repair dropped one of its triangles or its
// triangles use two copies of one vertex (a concave n-gon whose fan overlapped itself): whole, it
// would read back as it was read. Then each of its triangles becomes a polygon.
// face_polygon: per repaired triangle, its emitted polygon.
std::vector<Emitted> repaired_polygons(const MeshAttributes& in, const TriangleSoup& repaired,
                                       const BuildReport& report, int n_original, std::vector<int>& face_polygon) {
  const auto n_polygons = static_cast<std::size_t>(in.polygons.size());
  const auto origin = [&](int w) {
    return w < n_original ? w : report.origin[static_cast<std::size_t>(w - n_original)];
  };
  std::vector<int> kept(n_polygons, 0), read(n_polygons, 0);
  std::vector<char> split(n_polygons, 0);
  std::vector<std::vector<int>> faces_of(n_polygons);
  std::unordered_map<std::int64_t, int> renamed;  // polygon * n_original + read vertex -> repaired one
  for (int p : in.triangle_polygon) ++read[static_cast<std::size_t>(p)];
  for (std::size_t f = 0; f < repaired.faces.size(); ++f) {
    const auto t = static_cast<std::size_t>(report.face_origin.at(f));
    if (t >= in.triangle_polygon.size()) throw InternalError("repaired_attributes: a face has no polygon");
    const auto p = static_cast<std::size_t>(in.triangle_polygon[t]);
    ++kept[p];
    faces_of[p].push_back(static_cast<int>(f));
    for (int w : repaired.faces[f]) {
      const auto [it, added] = renamed.try_emplace(static_cast<std::int64_t>(p) * n_original + origin(w), w);
      if (!added && it->second != w) split[p] = 1;
    }
  }
  std::vector<Emitted> out;
  face_polygon.assign(repaired.faces.size(), -1);
  for (std::size_t p = 0; p < n_polygons; ++p) {
    if (kept[p] == 0) continue;
    const int begin = in.polygons.offsets[p], n = in.polygons.corner_count(static_cast<int>(p));
    const auto read_corner = [&](int v) {  // the first corner of the read polygon on vertex v
      for (int j = 0; j < n; ++j)
        if (in.polygons.corners[static_cast<std::size_t>(begin + j)] == v) return begin + j;
      return -1;
    };
    if (!split[p] && kept[p] == read[p]) {
      Emitted e{static_cast<int>(p), {}, {}};
      for (int j = 0; j < n; ++j) {
        const int v = in.polygons.corners[static_cast<std::size_t>(begin + j)];
        const auto it = renamed.find(static_cast<std::int64_t>(p) * n_original + v);
        e.corners.push_back(it == renamed.end() ? v : it->second);
        e.from.push_back(begin + j);
      }
      for (int f : faces_of[p]) face_polygon[static_cast<std::size_t>(f)] = static_cast<int>(out.size());
      out.push_back(std::move(e));
      continue;
    }
    for (int f : faces_of[p]) {
      Emitted e{static_cast<int>(p), {}, {}};
      for (int w : repaired.faces[static_cast<std::size_t>(f)]) {
        e.corners.push_back(w);
        e.from.push_back(read_corner(origin(w)));
      }
      face_polygon[static_cast<std::size_t>(f)] = static_cast<int>(out.size());
      out.push_back(std::move(e));
    }
  }
  return out;
}

// The attributes of a soup with `n_original` vertices after from_soup repaired it into `repaired`
// (report: what it changed, with face_origin).
MeshAttributes repaired_attributes(const MeshAttributes& in, const TriangleSoup& repaired, const BuildReport& report,
                                   int n_original) {
  MeshAttributes out = in;
  copy_vertex_rows(out.vertex, report.origin);
  out.triangle_polygon.clear();
  if (in.polygons.size() == 0) return out;
  const std::vector<Emitted> emitted = repaired_polygons(in, repaired, report, n_original, out.triangle_polygon);
  out.polygons = {};
  for (const Emitted& e : emitted) out.polygons.add(e.corners);
  for (CornerAttribute* a : {&out.uv, &out.normal}) {
    if (a->empty()) continue;
    const CornerAttribute& was = a == &out.uv ? in.uv : in.normal;
    a->index.clear();
    for (const Emitted& e : emitted)
      for (int c : e.from)
        a->index.push_back(
            c >= 0 && static_cast<std::size_t>(c) < was.index.size() ? was.index[static_cast<std::size_t>(c)] : -1);
  }
  for (std::size_t i = 0; i < out.face.size(); ++i) {  // a split polygon's row goes to each of its triangles
    const auto w = static_cast<std::size_t>(in.face[i].width);
    out.face[i].values.clear();
    for (const Emitted& e : emitted)
      for (std::size_t c = 0; c < w; ++c)
        out.face[i].values.push_back(in.face[i].values.at(static_cast<std::size_t>(e.source) * w + c));
  }
  return out;
}

}  // namespace

Mesh manifold_mesh(const TriangleSoup& soup, const std::string& path) {
  try {
    return Mesh::from_soup(soup);
  } catch (const TopologyError& e) {
    throw TopologyError(
        path + ": " + e.what() + " (`freeform convert --repair " + path +
        " OUT` writes a repaired copy that keeps the file's polygons, texture coordinates and colours)");
  }
}

BuildReport repair(ReadResult& file, const std::string& path, std::string& lost) {
  BuildReport report;
  TriangleSoup repaired = Mesh::from_soup(file.soup, BuildOptions{.repair = true}, &report).to_soup();
  if (repaired.faces.empty() && !file.soup.faces.empty())
    throw TopologyError(path + ": every face repeats a vertex: the repair would leave no face");
  lost.clear();
  if (!report.changed()) return report;
  file.attributes =
      repaired_attributes(file.attributes, repaired, report, static_cast<int>(file.soup.positions.size()));
  file.soup = std::move(repaired);
  if (file.source && !file.source->kept_only_by_rewrite().empty())
    lost = "the file's " + file.source->kept_only_by_rewrite() + " are not kept: the repaired mesh is written anew";
  file.source.reset();
  return report;
}

}  // namespace freeform
