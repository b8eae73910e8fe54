// Anisotropic bending domain: grown support -> per component LSCM -> area-weighted principal
// axes -> equal extents (docs/anisotropic.md).
#include "freeform/param/anisotropic.h"

#include "freeform/common/error.h"
#include "freeform/mesh/traversal.h"
#include "freeform/param/lscm.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace freeform {
namespace {

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Area-weighted principal axes of the planar region covered by the triangles, the principal
// extents and the equalized positions; returns the extents (major, minor).
std::array<double, 2> equalize_axes(const Mesh& patch, std::vector<Vec2>& uv) {
  double area = 0.0;
  Vec2 centroid = Vec2::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  for (Face f : patch.faces()) {
    const auto v = patch.vertices(f);
    const Vec2& a = uv[static_cast<std::size_t>(v[0].idx())];
    const Vec2& b = uv[static_cast<std::size_t>(v[1].idx())];
    const Vec2& c = uv[static_cast<std::size_t>(v[2].idx())];
    const double t = 0.5 * std::abs(cross2(b - a, c - a));
    const Vec2 s = a + b + c;
    area += t;
    centroid += t * s / 3.0;
    // Integral of x x^T over the triangle: A / 12 (sum p p^T + s s^T).
    second += t / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  centroid /= area;
  const Eigen::Matrix2d cov = second / area - centroid * centroid.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Vec2 e1 = eig.eigenvectors().col(1).normalized();  // major axis (largest eigenvalue)
  const Vec2 e2(-e1.y(), e1.x());                           // right-handed: no reflection
  double lo1 = std::numeric_limits<double>::max(), hi1 = -lo1, lo2 = lo1, hi2 = -lo1;
  for (Vec2& q : uv) {
    const Vec2 d = q - centroid;
    q = Vec2(d.dot(e1), d.dot(e2));
    lo1 = std::min(lo1, q.x());
    hi1 = std::max(hi1, q.x());
    lo2 = std::min(lo2, q.y());
    hi2 = std::max(hi2, q.y());
  }
  const double x1 = hi1 - lo1, x2 = hi2 - lo2;
  if (x1 > 0.0 && x2 > 0.0) {
    const double target = std::sqrt(x1 * x2);  // keeps the area
    for (Vec2& q : uv) q = Vec2(q.x() * target / x1, q.y() * target / x2);
  }
  return {x1, x2};
}

// The patch: vertices within k rings of the support, faces with all three corners in it;
// global[i] is the mesh vertex of patch vertex i.
TriangleSoup grown_support(const Mesh& mesh, std::span<const Vertex> support, int k, std::vector<Vertex>& global) {
  const VertexData<int> dist = ring_distance(mesh, support, k);
  std::vector<int> local(static_cast<std::size_t>(mesh.n_vertices()), -1);
  TriangleSoup soup;
  for (Face f : mesh.faces()) {
    const auto v = mesh.vertices(f);
    if (dist[v[0]] < 0 || dist[v[1]] < 0 || dist[v[2]] < 0) continue;
    Tri t{};
    for (std::size_t c = 0; c < 3; ++c) {
      int& l = local[static_cast<std::size_t>(v[c].idx())];
      if (l < 0) {
        l = static_cast<int>(global.size());
        global.push_back(v[c]);
        soup.positions.push_back(mesh.position(v[c]));
      }
      t[c] = l;
    }
    soup.faces.push_back(t);
  }
  return soup;
}

// The faces of component c of the patch as a soup; back[i] is the patch vertex of its vertex i.
TriangleSoup component_soup(const Mesh& patch, const Components& comp, int c, std::vector<int>& back) {
  TriangleSoup part;
  std::vector<int> sub(static_cast<std::size_t>(patch.n_vertices()), -1);
  for (Face f : patch.faces()) {
    if (comp.face_component[f] != c) continue;
    const auto v = patch.vertices(f);
    Tri t{};
    for (std::size_t i = 0; i < 3; ++i) {
      int& l = sub[static_cast<std::size_t>(v[i].idx())];
      if (l < 0) {
        l = static_cast<int>(back.size());
        back.push_back(v[i].idx());
        part.positions.push_back(patch.position(v[i]));
      }
      t[i] = l;
    }
    part.faces.push_back(t);
  }
  return part;
}

}  // namespace

AnisotropicDomain anisotropic_domain(const Mesh& mesh, std::span<const Vertex> support, int k) {
  const auto t0 = std::chrono::steady_clock::now();
  if (k < 1) throw InvalidInput("anisotropic domain: order k = " + std::to_string(k) + " must be at least 1");
  for (Vertex v : support)
    if (!v.is_valid() || v.idx() >= mesh.n_vertices())
      throw InvalidInput("anisotropic domain: support vertex " + std::to_string(v.idx()) + " is not in the mesh");
  AnisotropicDomain out;
  const auto finish = [&]() -> AnisotropicDomain {
    out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (!out.used) out.positions = VertexData<Vec3>();
    return std::move(out);
  };

  std::vector<Vertex> global;
  const TriangleSoup soup = grown_support(mesh, support, k, global);
  out.patch_vertices = static_cast<int>(global.size());
  out.patch_faces = static_cast<int>(soup.faces.size());
  if (soup.faces.empty()) {
    out.fallback = "the support has no triangle to parametrize";
    return finish();
  }
  BuildOptions repair;
  repair.repair = true;
  BuildReport report;
  const Mesh patch = Mesh::from_soup(soup, repair, &report);
  if (report.changed()) {
    const int v = report.origin.empty() ? -1 : global[static_cast<std::size_t>(report.origin.front())].idx();
    out.fallback = "the support grown by " + std::to_string(k) + " rings is not manifold (two fans of triangles meet at vertex " +
                   std::to_string(v) + "); grow or smooth the support";
    return finish();
  }
  const PatchTopology topo = patch_topology(patch);
  out.components = topo.components;
  out.genus = topo.genus;
  if (topo.genus > 0) {
    out.fallback = "the support grown by " + std::to_string(k) + " rings has genus " + std::to_string(topo.genus) +
                   " (it contains a handle of the surface), which has no conformal map to the plane";
    return finish();
  }

  // One LSCM per connected component (the system is block diagonal across them).
  const Components comp = connected_components(patch);
  out.positions = mesh.positions();
  double largest = -1.0;
  for (int c = 0; c < comp.count; ++c) {
    std::vector<int> back;
    const TriangleSoup part = component_soup(patch, comp, c, back);
    if (part.faces.empty()) continue;
    const Mesh piece = Mesh::from_soup(part);
    if (boundary_loops(piece).empty()) {
      out.fallback = "the support grown by " + std::to_string(k) +
                     " rings covers a closed part of the surface (no boundary to map to the plane)";
      return finish();
    }
    LscmResult map;
    try {
      map = lscm(piece);
    } catch (const Error& e) {  // e.g. a numerically singular system on a degenerate patch
      out.fallback = std::string("the conformal map of the support failed: ") + e.what();
      return finish();
    }
    out.angle_distortion_max = std::max(out.angle_distortion_max, map.distortion.angle_max);
    out.flipped += map.distortion.flipped;
    double area = 0.0;
    for (Face f : piece.faces()) {
      const auto v = piece.vertices(f);
      area += (piece.position(v[1]) - piece.position(v[0])).cross(piece.position(v[2]) - piece.position(v[0])).norm();
    }
    const std::array<double, 2> ext = equalize_axes(piece, map.uv);
    if (area > largest) {
      largest = area;
      out.extents = ext;
    }
    // Equalizing is a rotation and positive scales: it cannot flip, so check once here.
    if (!flipped_faces(piece, map.uv).empty() && out.flipped == 0) out.flipped = 1;
    for (std::size_t i = 0; i < back.size(); ++i) {
      const Vec2& q = map.uv[i];
      out.positions[global[static_cast<std::size_t>(back[i])]] = Vec3(q.x(), q.y(), 0.0);
    }
  }
  if (out.flipped > 0) {
    out.fallback = std::to_string(out.flipped) + " parameter triangle" + (out.flipped > 1 ? "s" : "") +
                   " flipped in the conformal map of the support grown by " + std::to_string(k) + " rings";
    return finish();
  }
  out.used = true;
  return finish();
}

}  // namespace freeform
