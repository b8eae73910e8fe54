#include "freeform/mesh/validation.h"

#include "freeform/mesh/mesh.h"
#include "freeform/mesh/soup_topology.h"
#include "freeform/mesh/traversal.h"

#include <bit>
#include <cstdint>
#include <unordered_map>

namespace freeform {
namespace {

struct PositionKey {
  std::uint64_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const noexcept {
    std::uint64_t h = k.x * 0x9E3779B97F4A7C15ull;
    h ^= k.y + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= k.z + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

std::uint64_t bits(double d) { return std::bit_cast<std::uint64_t>(d == 0.0 ? 0.0 : d); }  // -0 == +0

bool zero_area(const TriangleSoup& soup, const Tri& t) {
  const Vec3 &a = soup.positions[t[0]], &b = soup.positions[t[1]], &c = soup.positions[t[2]];
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return (b - a).cross(c - a).norm() <= 1e-12 * longest2;
}

void summarize_topology(const Mesh& mesh, ValidationReport& r) {
  const Components comps = connected_components(mesh);
  std::vector<ComponentSummary> all(comps.count);
  for (Vertex v : mesh.vertices()) all[comps.vertex_component[v]].vertices++;
  for (Face f : mesh.faces()) all[comps.face_component[f]].faces++;
  for (Edge e : mesh.edges()) all[comps.vertex_component[mesh.to_vertex(mesh.halfedge(e, 0))]].edges++;
  for (const auto& loop : boundary_loops(mesh)) all[comps.vertex_component[mesh.to_vertex(loop.front())]].boundary_loops++;
  for (auto& c : all) {
    if (c.faces == 0) continue;  // an unreferenced vertex
    c.euler_characteristic = c.vertices - c.edges + c.faces;
    c.genus = (2 - c.euler_characteristic - c.boundary_loops) / 2;
    r.components.push_back(c);
    r.boundary_loops += c.boundary_loops;
    r.euler_characteristic += c.euler_characteristic;
    r.genus += c.genus;
  }
}

}  // namespace

std::vector<std::array<int, 2>> coincident_positions(const std::vector<Vec3>& positions) {
  std::unordered_map<PositionKey, int, PositionKeyHash> first;
  first.reserve(positions.size());
  std::vector<std::array<int, 2>> dups;
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const Vec3& p = positions[v];
    auto [it, inserted] = first.try_emplace(PositionKey{bits(p.x()), bits(p.y()), bits(p.z())}, static_cast<int>(v));
    if (!inserted) dups.push_back({it->second, static_cast<int>(v)});
  }
  return dups;
}

ValidationReport validate(const TriangleSoup& soup) {
  ValidationReport r;
  r.vertices = static_cast<int>(soup.positions.size());
  r.faces = static_cast<int>(soup.faces.size());
  // Range and finiteness problems make the rest meaningless: from_soup throws on them.
  const Mesh repaired = Mesh::from_soup(soup, BuildOptions{.repair = true});

  std::vector<Tri> faces;
  std::vector<char> referenced(soup.positions.size(), 0);
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const Tri& t = soup.faces[f];
    for (int i : t) referenced[i] = 1;
    if (detail::has_repeated_index(t)) {
      r.repeated_index_faces.push_back(static_cast<int>(f));
      continue;
    }
    faces.push_back(t);
    if (zero_area(soup, t)) r.zero_area_faces.push_back(static_cast<int>(f));
  }
  for (std::size_t v = 0; v < referenced.size(); ++v)
    if (!referenced[v]) r.unreferenced_vertices.push_back(static_cast<int>(v));

  const detail::SoupTopology topo = detail::analyze_soup(r.vertices, faces);
  r.nonmanifold_edges = topo.nonmanifold_edges;
  r.inconsistent_edges = topo.inconsistent_edges;
  for (int v = 0; v < r.vertices; ++v)
    if (topo.fan_count[v] > 1) r.nonmanifold_vertices.push_back(v);
  r.duplicate_vertices = coincident_positions(soup.positions);
  summarize_topology(repaired, r);
  return r;
}

}  // namespace freeform
