#include "freeform/mesh/mesh.h"

#include "freeform/common/error.h"
#include "freeform/mesh/soup_topology.h"

#include <cmath>
#include <sstream>

namespace freeform {
namespace {

constexpr std::size_t kMaxListed = 10;  // elements named in one error message

std::string edge_list(const std::vector<std::array<int, 2>>& edges) {
  std::ostringstream out;
  for (std::size_t i = 0; i < edges.size() && i < kMaxListed; ++i) out << (i ? ", " : "") << "(" << edges[i][0] << ", " << edges[i][1] << ")";
  if (edges.size() > kMaxListed) out << ", ... (" << edges.size() << " in all)";
  return out.str();
}

void check_soup(const TriangleSoup& soup) {
  const auto n = static_cast<long long>(soup.positions.size());
  if (n > (1LL << 30)) throw InvalidInput("mesh has too many vertices (" + std::to_string(n) + ")");
  if (soup.faces.size() > (std::size_t{1} << 29)) throw InvalidInput("mesh has too many faces");
  for (std::size_t v = 0; v < soup.positions.size(); ++v)
    if (!soup.positions[v].allFinite()) throw InvalidInput("vertex " + std::to_string(v) + " has a non-finite coordinate");
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    for (int i : soup.faces[f])
      if (i < 0 || i >= n)
        throw InvalidInput("face " + std::to_string(f) + " references vertex " + std::to_string(i) + ", but the mesh has " +
                           std::to_string(n) + " vertices");
}

// Removes faces with a repeated index (repair) or refuses them.
std::vector<Tri> usable_faces(const TriangleSoup& soup, bool repair, BuildReport& report) {
  std::vector<Tri> faces;
  faces.reserve(soup.faces.size());
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const Tri& t = soup.faces[f];
    if (!detail::has_repeated_index(t)) {
      faces.push_back(t);
      if (repair) report.face_origin.push_back(static_cast<int>(f));
      continue;
    }
    const std::string what = "face " + std::to_string(f) + " (" + std::to_string(t[0]) + ", " + std::to_string(t[1]) +
                             ", " + std::to_string(t[2]) + ") repeats a vertex";
    if (!repair) throw TopologyError(what + "; rerun with repair to drop such faces");
    ++report.dropped_faces;
    if (report.changes.size() < 100) report.changes.push_back("dropped " + what);
  }
  return faces;
}

// Gives every extra fan of a vertex its own new vertex (appended), rewriting `faces`.
void split_fans(const detail::SoupTopology& topo, std::vector<Tri>& faces, std::vector<Vec3>& positions,
                BuildReport& report) {
  const int n_original = static_cast<int>(positions.size());
  std::vector<int> first_new(n_original, -1);
  for (int v = 0; v < n_original; ++v) {
    if (topo.fan_count[v] <= 1) continue;
    first_new[v] = static_cast<int>(positions.size());
    ++report.split_vertices;
    for (int k = 1; k < topo.fan_count[v]; ++k) {
      positions.push_back(positions[v]);
      report.origin.push_back(v);
    }
    if (report.changes.size() < 100)
      report.changes.push_back("split vertex " + std::to_string(v) + " into " + std::to_string(topo.fan_count[v]) +
                               " (new vertices " + std::to_string(first_new[v]) + ".." +
                               std::to_string(first_new[v] + topo.fan_count[v] - 2) + ")");
  }
  report.added_vertices = static_cast<int>(positions.size()) - n_original;
  for (std::size_t c = 0; c < faces.size() * 3; ++c) {
    int& v = faces[c / 3][c % 3];
    if (topo.fan[c] > 0) v = first_new[v] + topo.fan[c] - 1;
  }
}

}  // namespace

Mesh Mesh::from_soup(const TriangleSoup& soup, const BuildOptions& options, BuildReport* report_out) {
  check_soup(soup);
  BuildReport report;
  std::vector<Tri> faces = usable_faces(soup, options.repair, report);
  std::vector<Vec3> positions = soup.positions;
  const int n_original = static_cast<int>(positions.size());
  detail::SoupTopology topo = detail::analyze_soup(n_original, faces);

  std::vector<int> bad_vertices;
  for (int v = 0; v < n_original; ++v)
    if (topo.fan_count[v] > 1) bad_vertices.push_back(v);
  if (!bad_vertices.empty()) {
    if (!options.repair) {
      std::string msg = "mesh is not manifold:";
      if (!topo.nonmanifold_edges.empty()) msg += " non-manifold edges " + edge_list(topo.nonmanifold_edges) + ";";
      if (!topo.inconsistent_edges.empty())
        msg += " inconsistently oriented faces across edges " + edge_list(topo.inconsistent_edges) + ";";
      std::vector<std::array<int, 2>> as_pairs;
      for (int v : bad_vertices) as_pairs.push_back({v, topo.fan_count[v]});
      msg += " vertices with several fans (vertex, fans) " + edge_list(as_pairs) + ";";
      throw TopologyError(msg + " rerun with repair to split these vertices");
    }
    split_fans(topo, faces, positions, report);
  }

  Mesh m;
  const int nv = static_cast<int>(positions.size());
  const int nf = static_cast<int>(faces.size());
  const int n_directed = 3 * nf;
  m.positions_ = VertexData<Vec3>(std::move(positions));
  m.v_halfedge_.resize(nv);
  m.f_halfedge_.resize(nf);

  // Halfedge ids: glued directed edges share an edge; unglued ones get a boundary opposite.
  std::vector<int> he_of(n_directed, -1);
  int n_edges = 0;
  for (int d = 0; d < n_directed; ++d) {
    if (he_of[d] >= 0) continue;
    he_of[d] = 2 * n_edges;
    if (topo.twin[d] >= 0) he_of[topo.twin[d]] = 2 * n_edges + 1;
    ++n_edges;
  }
  const int nh = 2 * n_edges;
  m.he_to_.resize(nh);
  m.he_next_.resize(nh);
  m.he_prev_.resize(nh);
  m.he_face_.resize(nh);
  VertexData<Halfedge> out_boundary(nv);
  for (int d = 0; d < n_directed; ++d) {
    const int f = d / 3, i = d % 3;
    const Halfedge h(he_of[d]);
    const Vertex a(faces[f][i]), b(faces[f][(i + 1) % 3]);
    m.he_to_[h] = b;
    m.he_face_[h] = Face(f);
    m.he_next_[h] = Halfedge(he_of[3 * f + (i + 1) % 3]);
    m.he_prev_[h] = Halfedge(he_of[3 * f + (i + 2) % 3]);
    if (!m.v_halfedge_[a].is_valid()) m.v_halfedge_[a] = h;
    if (topo.twin[d] < 0) {
      const Halfedge o = m.opposite(h);  // b -> a on the boundary
      m.he_to_[o] = a;
      m.he_face_[o] = Face();
      FF_CHECK(!out_boundary[b].is_valid(), "two boundary halfedges leave one vertex");
      out_boundary[b] = o;
    }
  }
  for (int f = 0; f < nf; ++f) m.f_halfedge_[Face(f)] = Halfedge(he_of[3 * f]);
  for (Halfedge h : m.halfedges()) {
    if (m.he_face_[h].is_valid()) continue;
    const Halfedge n = out_boundary[m.he_to_[h]];
    FF_CHECK(n.is_valid(), "open boundary loop");
    m.he_next_[h] = n;
    m.he_prev_[n] = h;
  }
  for (Vertex v : m.vertices())
    if (out_boundary[v].is_valid()) m.v_halfedge_[v] = out_boundary[v];

  if (report_out) *report_out = std::move(report);
  return m;
}

TriangleSoup Mesh::to_soup() const {
  TriangleSoup soup;
  soup.positions = positions_.raw();
  soup.faces.reserve(f_halfedge_.size());
  for (Face f : faces()) {
    const auto v = vertices(f);
    soup.faces.push_back({v[0].idx(), v[1].idx(), v[2].idx()});
  }
  return soup;
}

std::array<Vertex, 3> Mesh::vertices(Face f) const {
  const Halfedge h = f_halfedge_[f];
  return {from_vertex(h), to_vertex(h), to_vertex(next(h))};
}

std::array<Halfedge, 3> Mesh::halfedges(Face f) const {
  const Halfedge h = f_halfedge_[f];
  return {h, next(h), prev(h)};
}

int Mesh::valence(Vertex v) const {
  int n = 0;
  for ([[maybe_unused]] Halfedge h : outgoing(v)) ++n;
  return n;
}

Halfedge Mesh::find_halfedge(Vertex a, Vertex b) const {
  for (Halfedge h : outgoing(a))
    if (to_vertex(h) == b) return h;
  return Halfedge();
}

Eigen::MatrixX3d Mesh::position_matrix() const {
  Eigen::MatrixX3d x(n_vertices(), 3);
  for (Vertex v : vertices()) x.row(v.idx()) = positions_[v].transpose();
  return x;
}

void Mesh::set_positions(const Eigen::MatrixX3d& x) {
  if (x.rows() != n_vertices())
    throw InvalidInput("set_positions: " + std::to_string(x.rows()) + " rows for " + std::to_string(n_vertices()) +
                       " vertices");
  for (Vertex v : vertices()) positions_[v] = x.row(v.idx()).transpose();
}

HalfedgesAroundVertex::HalfedgesAroundVertex(const Mesh& m, Vertex v) : mesh_(&m), start_(m.halfedge(v)) {}

HalfedgesAroundVertex::iterator& HalfedgesAroundVertex::iterator::operator++() {
  h = mesh->cw_rotated(h);
  moved = true;
  return *this;
}

}  // namespace freeform
