// LSCM (Levy et al. 2002) as sparse least squares: two Cauchy-Riemann rows per face, two pins,
// normal equations solved by SparseSolver (symmetric -> CHOLMOD).
#include "freeform/param/lscm.h"

#include "freeform/common/error.h"
#include "freeform/mesh/traversal.h"
#include "freeform/numerics/sparse_solver.h"
#include "freeform/operators/face_geometry.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace freeform {
namespace {

// Corner positions of face f in an orthonormal frame of its plane (counter-clockwise).
struct LocalTriangle {
  std::array<Vertex, 3> v;
  std::array<Vec2, 3> p;
  double area = 0.0;
  bool degenerate = true;
};

LocalTriangle local_triangle(const Mesh& mesh, Face f) {
  LocalTriangle t;
  t.v = mesh.vertices(f);
  const Vec3& a = mesh.position(t.v[0]);
  const Vec3& b = mesh.position(t.v[1]);
  const Vec3& c = mesh.position(t.v[2]);
  const detail::TriangleGeometry g = detail::triangle_geometry(a, b, c);
  t.degenerate = g.degenerate;
  if (t.degenerate) return t;
  const Vec3 e1 = (b - a).normalized();
  const Vec3 n = (b - a).cross(c - a);
  const Vec3 e2 = n.cross(b - a).normalized();
  t.p = {Vec2(0, 0), Vec2((b - a).dot(e1), 0.0), Vec2((c - a).dot(e1), (c - a).dot(e2))};
  t.area = 0.5 * g.double_area;
  return t;
}

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double signed_uv_area(const Mesh& mesh, Face f, std::span<const Vec2> uv) {
  const auto v = mesh.vertices(f);
  const Vec2& a = uv[static_cast<std::size_t>(v[0].idx())];
  return 0.5 * cross2(uv[static_cast<std::size_t>(v[1].idx())] - a, uv[static_cast<std::size_t>(v[2].idx())] - a);
}

void check_uv(const Mesh& mesh, std::span<const Vec2> uv) {
  if (uv.size() != static_cast<std::size_t>(mesh.n_vertices()))
    throw InvalidInput("parametrization has " + std::to_string(uv.size()) + " entries, the mesh " +
                       std::to_string(mesh.n_vertices()) + " vertices");
}

// Boundary vertices far apart: the one farthest from boundary vertex 0, then the farthest
// from that one (3D distance).
std::array<Vertex, 2> far_pins(const Mesh& mesh, const std::vector<std::vector<Halfedge>>& loops) {
  std::vector<Vertex> boundary;
  for (const auto& loop : loops)
    for (Halfedge h : loop) boundary.push_back(mesh.to_vertex(h));
  const auto farthest = [&](Vertex from) {
    Vertex best = boundary.front();
    double d = -1.0;
    for (Vertex w : boundary) {
      const double dw = (mesh.position(w) - mesh.position(from)).squaredNorm();
      if (dw > d) {
        d = dw;
        best = w;
      }
    }
    return best;
  };
  const Vertex a = farthest(boundary.front());
  return {a, farthest(a)};
}

}  // namespace

PatchTopology patch_topology(const Mesh& mesh) {
  PatchTopology t;
  const Components comp = connected_components(mesh);
  const auto n = static_cast<std::size_t>(comp.count);
  std::vector<long long> chi(n, 0);
  std::vector<int> loops(n, 0);
  std::vector<char> has_face(n, 0);
  for (Vertex v : mesh.vertices())
    if (!mesh.is_isolated(v)) ++chi[static_cast<std::size_t>(comp.vertex_component[v])];
  for (Edge e : mesh.edges())
    --chi[static_cast<std::size_t>(comp.vertex_component[mesh.to_vertex(mesh.halfedge(e, 0))])];
  for (Face f : mesh.faces()) {
    const auto c = static_cast<std::size_t>(comp.face_component[f]);
    ++chi[c];
    has_face[c] = 1;
  }
  for (const auto& loop : boundary_loops(mesh)) ++loops[static_cast<std::size_t>(comp.vertex_component[mesh.to_vertex(loop.front())])];
  for (std::size_t c = 0; c < n; ++c) {
    if (!has_face[c]) continue;
    ++t.components;
    t.boundary_loops += loops[c];
    t.genus += static_cast<int>((2 - loops[c] - chi[c]) / 2);
  }
  return t;
}

std::vector<Face> flipped_faces(const Mesh& mesh, std::span<const Vec2> uv) {
  check_uv(mesh, uv);
  std::vector<Face> out;
  for (Face f : mesh.faces()) {
    if (local_triangle(mesh, f).degenerate) continue;
    if (!(signed_uv_area(mesh, f, uv) > 0.0)) out.push_back(f);
  }
  return out;
}

ParamDistortion measure_distortion(const Mesh& mesh, std::span<const Vec2> uv) {
  check_uv(mesh, uv);
  ParamDistortion d;
  double area3 = 0.0, area_uv = 0.0;
  std::vector<LocalTriangle> tris;
  tris.reserve(static_cast<std::size_t>(mesh.n_faces()));
  for (Face f : mesh.faces()) {
    tris.push_back(local_triangle(mesh, f));
    if (tris.back().degenerate) {
      ++d.degenerate;
      continue;
    }
    area3 += tris.back().area;
    area_uv += std::abs(signed_uv_area(mesh, f, uv));
  }
  const double s = area3 > 0.0 ? area_uv / area3 : 1.0;
  double wsum = 0.0;
  for (Face f : mesh.faces()) {
    const LocalTriangle& t = tris[static_cast<std::size_t>(f.idx())];
    if (t.degenerate) continue;
    const double a_uv = signed_uv_area(mesh, f, uv);
    if (!(a_uv > 0.0)) {
      ++d.flipped;
      continue;
    }
    Eigen::Matrix2d p, q;
    p << t.p[1] - t.p[0], t.p[2] - t.p[0];
    const auto u = [&](int k) { return uv[static_cast<std::size_t>(t.v[static_cast<std::size_t>(k)].idx())]; };
    q << u(1) - u(0), u(2) - u(0);
    const Eigen::Matrix2d j = q * p.inverse();
    // Singular values of a 2x2 matrix in closed form.
    const double e = 0.5 * (j(0, 0) + j(1, 1)), ff = 0.5 * (j(0, 0) - j(1, 1));
    const double g = 0.5 * (j(1, 0) + j(0, 1)), h = 0.5 * (j(1, 0) - j(0, 1));
    const double qq = std::hypot(e, h), rr = std::hypot(ff, g);
    const double s1 = qq + rr, s2 = std::abs(qq - rr);
    const double angle = s2 > 0.0 ? s1 / s2 - 1.0 : 1e300;
    const double area = std::abs(std::log(a_uv / (s * t.area)));
    d.angle_max = std::max(d.angle_max, angle);
    d.area_max = std::max(d.area_max, area);
    d.angle_mean += t.area * angle;
    d.area_mean += t.area * area;
    wsum += t.area;
  }
  if (wsum > 0.0) {
    d.angle_mean /= wsum;
    d.area_mean /= wsum;
  }
  return d;
}

LscmResult lscm(const Mesh& patch) {
  const int n = patch.n_vertices();
  if (n < 3 || patch.n_faces() == 0) throw InvalidInput("lscm: the patch has no triangle");
  for (Vertex v : patch.vertices()) {
    if (patch.is_isolated(v)) throw InvalidInput("lscm: vertex " + std::to_string(v.idx()) + " belongs to no triangle");
    if (!patch.position(v).allFinite()) throw InvalidInput("lscm: vertex " + std::to_string(v.idx()) + " is not finite");
  }
  const PatchTopology topo = patch_topology(patch);
  if (topo.components != 1)
    throw InvalidInput("lscm: the patch has " + std::to_string(topo.components) +
                       " connected components; parametrize each on its own");
  if (topo.boundary_loops == 0) throw InvalidInput("lscm: the patch is closed (no boundary loop); cut it open first");
  if (topo.genus > 0)
    throw TopologyError("lscm: the patch has genus " + std::to_string(topo.genus) +
                        "; a conformal map to the plane needs genus 0");

  LscmResult r;
  r.pins = far_pins(patch, boundary_loops(patch));
  const double pin_dist = (patch.position(r.pins[1]) - patch.position(r.pins[0])).norm();
  if (!(pin_dist > 0.0)) throw InvalidInput("lscm: all boundary vertices coincide");
  // Unknown index of each vertex (u at 2i, v at 2i+1), -1 for the pins.
  std::vector<int> col(static_cast<std::size_t>(n), 0);
  col[static_cast<std::size_t>(r.pins[0].idx())] = -1;
  col[static_cast<std::size_t>(r.pins[1].idx())] = -2;
  int n_free = 0;
  for (int& c : col)
    if (c >= 0) c = n_free++;
  const std::array<Vec2, 2> pin_uv = {Vec2(0, 0), Vec2(pin_dist, 0)};

  using Triplet = Eigen::Triplet<double>;
  std::vector<Triplet> tf;
  tf.reserve(static_cast<std::size_t>(patch.n_faces()) * 12);
  Eigen::MatrixXd rhs_rows = Eigen::MatrixXd::Zero(2 * patch.n_faces(), 1);
  int row = 0;
  for (Face f : patch.faces()) {
    const LocalTriangle t = local_triangle(patch, f);
    if (t.degenerate) continue;
    // grad f = 1/(2A) sum_k f_k R90(e_k), e_k = p_{k+2} - p_{k+1}; weight sqrt(A).
    const double w = 1.0 / (2.0 * std::sqrt(t.area));
    for (int k = 0; k < 3; ++k) {
      const Vec2 e = t.p[static_cast<std::size_t>((k + 2) % 3)] - t.p[static_cast<std::size_t>((k + 1) % 3)];
      const double cx = -e.y() * w, cy = e.x() * w;  // d/dx and d/dy coefficients of vertex k
      const int c = col[static_cast<std::size_t>(t.v[static_cast<std::size_t>(k)].idx())];
      // Row 0: u_x - v_y = 0; row 1: u_y + v_x = 0.
      if (c >= 0) {
        tf.emplace_back(row, 2 * c, cx);
        tf.emplace_back(row, 2 * c + 1, -cy);
        tf.emplace_back(row + 1, 2 * c, cy);
        tf.emplace_back(row + 1, 2 * c + 1, cx);
      } else {
        const Vec2& q = pin_uv[static_cast<std::size_t>(-c - 1)];
        rhs_rows(row, 0) -= cx * q.x() - cy * q.y();
        rhs_rows(row + 1, 0) -= cy * q.x() + cx * q.y();
      }
    }
    row += 2;
  }
  Eigen::SparseMatrix<double> m(row, 2 * n_free);
  m.setFromTriplets(tf.begin(), tf.end());
  tf = {};
  const Eigen::SparseMatrix<double> mt = m.transpose();
  Eigen::SparseMatrix<double> normal = mt * m;
  normal.makeCompressed();
  const Eigen::MatrixXd rhs = mt * rhs_rows.topRows(row);
  const SparseSolver solver(std::move(normal), true);
  const Eigen::MatrixXd x = solver.solve(rhs);

  r.uv.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const int c = col[static_cast<std::size_t>(i)];
    r.uv[static_cast<std::size_t>(i)] = c >= 0 ? Vec2(x(2 * c, 0), x(2 * c + 1, 0)) : pin_uv[static_cast<std::size_t>(-c - 1)];
  }
  // Scale (about pin 0) so that the uv area equals the 3D area: extents are in mesh units.
  double area3 = 0.0, area_uv = 0.0;
  for (Face f : patch.faces()) {
    const LocalTriangle t = local_triangle(patch, f);
    if (t.degenerate) continue;
    area3 += t.area;
    area_uv += signed_uv_area(patch, f, r.uv);
  }
  if (area_uv > 0.0 && area3 > 0.0) {
    const double s = std::sqrt(area3 / area_uv);
    for (Vec2& q : r.uv) q *= s;
  }
  r.distortion = measure_distortion(patch, r.uv);
  return r;
}

}  // namespace freeform
