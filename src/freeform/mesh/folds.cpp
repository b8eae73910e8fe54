#include "freeform/mesh/folds.h"

#include "freeform/common/error.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace freeform {
namespace {

// The angle between the normals of triangles (a, b, c) and (b, a, d) sharing edge a-b; -1 if
// either triangle has no normal (zero area or non-finite).
double dihedral(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 n1 = (b - a).cross(c - a);
  const Vec3 n2 = (a - b).cross(d - b);
  const double l = n1.norm() * n2.norm();
  if (!(l > 0.0) || !std::isfinite(l)) return -1.0;
  return std::atan2(n1.cross(n2).norm(), n1.dot(n2));
}

double dihedral(const std::array<int, 4>& q, const VertexData<Vec3>& p) {
  const Vec3* x = p.raw().data();
  return dihedral(x[q[0]], x[q[1]], x[q[2]], x[q[3]]);
}

}  // namespace

FoldCounter::FoldCounter(const Mesh& mesh, const VertexData<Vec3>& rest, std::span<const Vertex> moving,
                         double threshold_degrees)
    : threshold_(threshold_degrees * std::numbers::pi / 180.0), n_vertices_(mesh.n_vertices()) {
  if (rest.size() != static_cast<std::size_t>(mesh.n_vertices()))
    throw InvalidInput("folds: rest positions have " + std::to_string(rest.size()) + " entries, the mesh has " +
                       std::to_string(mesh.n_vertices()) + " vertices");
  std::vector<char> moves(static_cast<std::size_t>(mesh.n_vertices()), 0);
  for (Vertex v : moving) moves[static_cast<std::size_t>(v.idx())] = 1;
  std::vector<char> watched(static_cast<std::size_t>(mesh.n_edges()), 0);
  for (Vertex v : moving) {
    for (Halfedge out : HalfedgesAroundVertex(mesh, v)) {
      // Every edge of a face around v can change its angle.
      for (Halfedge h : {out, mesh.opposite(out)}) {
        if (mesh.is_boundary(h)) continue;
        for (Halfedge e : mesh.halfedges(mesh.face(h))) watched[static_cast<std::size_t>(mesh.edge(e).idx())] = 1;
      }
    }
  }
  for (Edge e : mesh.edges()) {
    if (!watched[static_cast<std::size_t>(e.idx())] || mesh.is_boundary(e)) continue;
    const Halfedge h = mesh.halfedge(e, 0), o = mesh.halfedge(e, 1);
    const std::array<int, 4> q{mesh.from_vertex(h).idx(), mesh.to_vertex(h).idx(), mesh.to_vertex(mesh.next(h)).idx(),
                               mesh.to_vertex(mesh.next(o)).idx()};
    const double angle = dihedral(q, rest);
    if (angle < 0.0) continue;  // degenerate at rest: no angle to compare with
    quads_.push_back(q);
    rest_angle_.push_back(angle);
  }
}

int FoldCounter::count(const VertexData<Vec3>& positions) const {
  if (positions.size() != static_cast<std::size_t>(n_vertices_))
    throw InvalidInput("folds: positions have " + std::to_string(positions.size()) + " entries, the mesh has " +
                       std::to_string(n_vertices_) + " vertices");
  int folded = 0;
  for (std::size_t i = 0; i < quads_.size(); ++i) {
    const double angle = dihedral(quads_[i], positions);
    if (angle < 0.0 || angle - rest_angle_[i] > threshold_) ++folded;
  }
  return folded;
}

int count_folded_edges(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<Vec3>& deformed,
                       double threshold_degrees) {
  std::vector<Vertex> all;
  for (Vertex v : mesh.vertices()) all.push_back(v);
  return FoldCounter(mesh, rest, all, threshold_degrees).count(deformed);
}

}  // namespace freeform
