#include "freeform/multires/operator_shape.h"

#include "freeform/bcm/bcm_solver.h"
#include "freeform/common/error.h"

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace freeform {
namespace {

// A foot-point triangle must keep its orientation against the membrane and keep this fraction
// of its area at least; steeper detail (walls, overhangs) makes the projection degenerate.
constexpr double kMinAreaRatio = 1e-3;

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
    if (!(foot.dot(ref) > 0.0) || !(foot.norm() > kMinAreaRatio * face_normal(mesh.positions(), f).norm())) ++bad;
  }
  out.overhanging = bad;
  if (bad > 0) {
    out.fallback = "the detail overhangs its base at " + std::to_string(bad) +
                   " triangles; the base bends with the detailed mesh's operator";
    out.positions = VertexData<Vec3>(0);
  }
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace freeform
