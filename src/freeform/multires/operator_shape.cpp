#include "freeform/multires/operator_shape.h"

#include "freeform/bcm/bcm_solver.h"
#include "freeform/common/error.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace freeform {
namespace {

// A foot-point triangle must keep its orientation against the membrane and may be squeezed to
// no less than this fraction of its size in any direction (a slope of 75 degrees against the
// base). Steeper detail (walls, overhangs) makes the projection degenerate, and so does detail
// as tall as its base is wide: the membrane of a long tube pinches toward its axis, so the
// "detail" is the whole radius and the base's cotangents blow up (docs/multires.md). Detail
// that stands on its base is squeezed far less (the survey's bumpy plane: 0.52).
constexpr double kMinStretch = 0.25;

// Smallest singular value of the affine map from triangle (a, b, c) to (p, q, r): how far the
// projection squeezes it in its most compressed direction.
double min_stretch(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 e1 = b - a, e2 = c - a;
  const double l1 = e1.norm();
  if (!(l1 > 0.0)) return 0.0;
  const Vec3 u = e1 / l1;
  const Vec3 w = e2 - e2.dot(u) * u;
  const double lw = w.norm();
  if (!(lw > 0.0)) return 0.0;
  // Rest frame coordinates (l1, 0) and (e2.u, lw); J = [q-p, r-p] * inverse of that 2x2.
  const Vec3 f1 = q - p, f2 = r - p;
  const Vec3 j1 = f1 / l1, j2 = (f2 - (e2.dot(u) / l1) * f1) / lw;
  const double g11 = j1.squaredNorm(), g22 = j2.squaredNorm(), g12 = j1.dot(j2);
  const double tr = 0.5 * (g11 + g22), det = g11 * g22 - g12 * g12;
  return std::sqrt(std::max(0.0, tr - std::sqrt(std::max(0.0, tr * tr - det))));
}

}  // namespace

OperatorShape base_operator_shape(const Mesh& mesh, const Regions& regions, const BcmSettings& settings,
                                  const Progress& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  OperatorShape out;
  if (settings.anisotropic) {
    out.fallback = "anisotropic bending discretizes on its own parameter domain";
    return out;
  }
  BcmSettings membrane = settings;
  membrane.order = 1;
  membrane.smoothness = {};
  Progress cancel_only;  // the caller's progress bar follows the main solver's stages
  cancel_only.cancel = progress.cancel;
  std::optional<BcmSolver> fill;
  try {
    fill.emplace(mesh, regions, membrane, cancel_only);
  } catch (const SolverError& e) {
    out.fallback = std::string("the membrane fill failed (") + e.what() + ")";
    return out;
  }
  VertexData<Vec3> base = mesh.positions();
  fill->evaluate(std::vector<Eigen::Affine3d>(static_cast<std::size_t>(fill->n_movable()), Eigen::Affine3d::Identity()), base);

  // Faces around the free vertices, with the membrane's area-weighted vertex normals.
  const std::vector<Vertex>& free = fill->free_vertices();
  std::vector<Face> faces;
  FaceData<char> seen(static_cast<std::size_t>(mesh.n_faces()), 0);
  for (Vertex v : free)
    for (Halfedge h : mesh.outgoing(v))
      if (const Face f = mesh.face(h); f.is_valid() && !seen[f]) {
        seen[f] = 1;
        faces.push_back(f);
      }
  VertexData<Vec3> normal(static_cast<std::size_t>(mesh.n_vertices()), Vec3::Zero());
  auto corners = [&](Face f) {
    const auto h = mesh.halfedges(f);
    return std::array<Vertex, 3>{mesh.from_vertex(h[0]), mesh.to_vertex(h[0]), mesh.to_vertex(h[1])};
  };
  auto face_normal = [&](const VertexData<Vec3>& p, Face f) {
    const auto c = corners(f);
    return Vec3((p[c[1]] - p[c[0]]).cross(p[c[2]] - p[c[0]]));
  };
  for (Face f : faces)
    for (Vertex v : corners(f)) normal[v] += face_normal(base, f);

  out.positions = mesh.positions();
  for (Vertex v : free) {
    const double n = normal[v].norm();
    if (!(n > 0.0)) {
      out.fallback = "the membrane fill is degenerate at vertex " + std::to_string(v.idx());
      out.positions = VertexData<Vec3>(0);
      return out;
    }
    const Vec3 u = normal[v] / n;
    out.positions[v] -= (mesh.position(v) - base[v]).dot(u) * u;
  }
  // All or nothing: mixing foot points with mesh positions where the detail overhangs gives an
  // operator whose metric jumps at the seam (measured: fandisk's creases bent by 50 degrees).
  int bad = 0;
  for (Face f : faces) {
    const auto c = corners(f);
    const Vec3 foot = face_normal(out.positions, f);
    const Vec3 ref = normal[c[0]] + normal[c[1]] + normal[c[2]];
    const double stretch = min_stretch(mesh.position(c[0]), mesh.position(c[1]), mesh.position(c[2]),
                                       out.positions[c[0]], out.positions[c[1]], out.positions[c[2]]);
    if (!(foot.dot(ref) > 0.0) || !(stretch >= kMinStretch)) ++bad;
  }
  out.overhanging = bad;
  if (bad > 0) {
    out.fallback = "the detail overhangs its base at " + std::to_string(bad) +
                   " triangles (foot points folded or squeezed below a quarter); the base bends with the detailed "
                   "mesh's operator";
    out.positions = VertexData<Vec3>(0);
  }
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace freeform
