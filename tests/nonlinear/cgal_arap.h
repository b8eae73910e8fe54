// The peer: CGAL's Surface_mesh_deformation (ARAP, spokes and rims, or SR-ARAP) on a Shape's
// support, handles and transforms, from the same start as Freeform (the rest, handles moved).
// Used by the gallery benchmark and its subset in the tests; CGAL never enters the library.
#pragma once

#include "survey_shapes.h"

#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_deformation.h>

#include <chrono>
#include <optional>

namespace freeform::test {

struct PeerResult {
  VertexData<Vec3> positions;
  double precompute_ms = 0, solve_ms = 0;
};

// CGAL stops when the relative energy change falls below 1e-6 or after `iterations`; nullopt
// if its preprocessing fails.
template <CGAL::Deformation_algorithm_tag Tag = CGAL::SPOKES_AND_RIMS>
std::optional<PeerResult> cgal_deform(const Shape& s, int iterations) {
  using Point = CGAL::Simple_cartesian<double>::Point_3;
  using SurfaceMesh = CGAL::Surface_mesh<Point>;
  using SmVertex = SurfaceMesh::Vertex_index;
  using Clock = std::chrono::steady_clock;
  auto ms_since = [](Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
  };
  auto sm_vertex = [](Vertex v) { return SmVertex(static_cast<SurfaceMesh::size_type>(v.idx())); };
  const TriangleSoup soup = s.mesh.to_soup();
  SurfaceMesh sm;
  for (const Vec3& x : soup.positions) sm.add_vertex(Point(x.x(), x.y(), x.z()));
  for (const Tri& f : soup.faces)
    sm.add_face(sm_vertex(Vertex(f[0])), sm_vertex(Vertex(f[1])), sm_vertex(Vertex(f[2])));
  PeerResult out;
  auto clock = Clock::now();
  CGAL::Surface_mesh_deformation<SurfaceMesh, CGAL::Default, CGAL::Default, Tag> d(sm);
  for (Vertex v : s.edit.support) d.insert_roi_vertex(sm_vertex(v));
  for (const EditHandle& h : s.edit.handles)
    for (Vertex v : h.vertices) d.insert_control_vertex(sm_vertex(v));
  if (!d.preprocess()) return std::nullopt;
  out.precompute_ms = ms_since(clock);
  for (const EditHandle& h : s.edit.handles)
    for (Vertex v : h.vertices) {
      const Vec3 y = *h.matrix * s.mesh.position(v);
      d.set_target_position(sm_vertex(v), Point(y.x(), y.y(), y.z()));
    }
  clock = Clock::now();
  d.deform(static_cast<unsigned>(iterations), 1e-6);
  out.solve_ms = ms_since(clock);
  out.positions = s.mesh.positions();
  for (Vertex v : s.mesh.vertices()) {
    const Point& q = sm.point(sm_vertex(v));
    out.positions[v] = Vec3(q.x(), q.y(), q.z());
  }
  return out;
}

}  // namespace freeform::test
