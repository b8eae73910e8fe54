#include "freeform/multires/operator_shape.h"

#include "freeform/bcm/bcm_solver.h"
#include "freeform/common/error.h"
#include "freeform/common/parallel.h"

#include <algorithm>
#include <atomic>
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

// A free vertex on the mesh's open boundary is lifted when the membrane fill passes it at more
// than this fraction of its mean edge length along the fill's normal. Measured
// (docs/nonlinear.md, "What the gallery found", 43): 0 on the survey's bumpy plane, whose sides
// are flat; 0.07-7 where the gallery's supports reach the curved open boundaries of 12
// libcgal-demo meshes, on which decomposing the detail folded more than the model without it.
constexpr double kLiftedBoundary = 0.05;

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

// The faces around the free vertices (those with a free corner) on the membrane fill `base`.
// Normals are gathered per vertex, so the loops over the free vertices run in parallel.
struct FillFaces {
  const Mesh& mesh;
  const Regions& regions;
  const VertexData<Vec3>& base;

  bool is_free(Vertex v) const { return regions.role(v) == Role::Free; }
  std::array<Vertex, 3> corners(Face f) const {
    const auto h = mesh.halfedges(f);
    return {mesh.from_vertex(h[0]), mesh.to_vertex(h[0]), mesh.to_vertex(h[1])};
  }
  Vec3 face_normal(const VertexData<Vec3>& p, Face f) const {
    const auto c = corners(f);
    return (p[c[1]] - p[c[0]]).cross(p[c[2]] - p[c[0]]);
  }
  // The membrane's area-weighted normal at v.
  Vec3 membrane_normal(Vertex v) const {
    Vec3 n = Vec3::Zero();
    for (Halfedge h : mesh.outgoing(v))
      if (const Face f = mesh.face(h); f.is_valid()) {
        const auto c = corners(f);
        if (is_free(c[0]) || is_free(c[1]) || is_free(c[2])) n += face_normal(base, f);
      }
    return n;
  }
  // Whether the fill passes boundary vertex v farther than kLiftedBoundary of its mean edge
  // length along the fill's normal n.
  bool lifted(Vertex v, const Vec3& n) const {
    double length = 0.0;
    int edges = 0;
    for (Halfedge h : mesh.outgoing(v)) {
      length += (mesh.position(mesh.to_vertex(h)) - mesh.position(v)).norm();
      ++edges;
    }
    return std::abs((mesh.position(v) - base[v]).dot(n.normalized())) > kLiftedBoundary * length / std::max(edges, 1);
  }
  // Faces whose foot points fold against the membrane or squeeze below kMinStretch; each face
  // is checked once, by its first free corner. normal: membrane_normal on the free vertices.
  int overhanging(const std::vector<Vertex>& free, const VertexData<Vec3>& normal, const VertexData<Vec3>& foot) const {
    std::atomic<int> count{0};
    parallel_for(static_cast<std::ptrdiff_t>(free.size()), 4096, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
      int bad = 0;
      for (std::ptrdiff_t i = lo; i < hi; ++i) {
        const Vertex v = free[static_cast<std::size_t>(i)];
        for (Halfedge h : mesh.outgoing(v)) {
          const Face f = mesh.face(h);
          if (!f.is_valid()) continue;
          const auto c = corners(f);
          if (std::any_of(c.begin(), c.end(), [&](Vertex w) { return is_free(w) && w.idx() < v.idx(); })) continue;
          Vec3 ref = Vec3::Zero();
          for (Vertex w : c) ref += is_free(w) ? normal[w] : membrane_normal(w);
          const double stretch = min_stretch(mesh.position(c[0]), mesh.position(c[1]), mesh.position(c[2]), foot[c[0]],
                                             foot[c[1]], foot[c[2]]);
          if (!(face_normal(foot, f).dot(ref) > 0.0) || !(stretch >= kMinStretch)) ++bad;
        }
      }
      count += bad;
    });
    return count.load();
  }
};

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
  std::optional<BcmRestSolution> fill;
  try {
    fill.emplace(bcm_rest_solution(mesh, regions, membrane, cancel_only));
  } catch (const SolverError& e) {
    out.fallback = std::string("the membrane fill failed (") + e.what() + ")";
    return out;
  }
  const FillFaces faces{mesh, regions, fill->positions};
  const std::vector<Vertex>& free = fill->free;
  const auto n_free = static_cast<std::ptrdiff_t>(free.size());
  // Read on the free vertices only, each written first by the loop below (Eigen's default
  // constructor leaves the array untouched: no serial fill of #V entries).
  VertexData<Vec3> normal(std::vector<Vec3>(static_cast<std::size_t>(mesh.n_vertices())));
  out.positions = mesh.positions();
  parallel_for(n_free, 4096, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    for (std::ptrdiff_t i = lo; i < hi; ++i) {
      const Vertex v = free[static_cast<std::size_t>(i)];
      normal[v] = faces.membrane_normal(v);
      const double n = normal[v].norm();
      if (!(n > 0.0)) continue;  // refused below
      const Vec3 u = normal[v] / n;
      out.positions[v] -= (mesh.position(v) - faces.base[v]).dot(u) * u;
    }
  });
  const auto degenerate = std::find_if(free.begin(), free.end(), [&](Vertex v) { return !(normal[v].norm() > 0.0); });
  if (degenerate != free.end()) {
    out.fallback = "the membrane fill is degenerate at vertex " + std::to_string(degenerate->idx());
    out.positions = VertexData<Vec3>(0);
    return out;
  }
  std::atomic<int> lifted{0};  // on the pool: a serial pass took 13 ms at 1M free vertices
  parallel_for(n_free, 4096, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
    int count = 0;
    for (std::ptrdiff_t i = lo; i < hi; ++i) {
      const Vertex v = free[static_cast<std::size_t>(i)];
      count += mesh.is_boundary(v) && faces.lifted(v, normal[v]);
    }
    lifted += count;
  });
  out.lifted_boundary = lifted.load();
  // All or nothing: mixing foot points with mesh positions where the detail overhangs gives an
  // operator whose metric jumps at the seam (measured: fandisk's creases bent by 50 degrees).
  const int bad = faces.overhanging(free, normal, out.positions);
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
