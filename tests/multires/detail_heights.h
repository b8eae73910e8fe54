// Detail heights as docs/multires.md defines them, computed independently of the multiresolution
// code: a free vertex's offset from a base along the base's area-weighted unit vertex normal.
// Shared by tests/multires and bench_gallery --linear-multires.
#pragma once

#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace freeform::test {

// Area-weighted unit vertex normals of the given positions.
inline VertexData<Vec3> vertex_normals(const Mesh& mesh, const VertexData<Vec3>& p) {
  VertexData<Vec3> n(static_cast<std::size_t>(mesh.n_vertices()), Vec3::Zero());
  for (Face f : mesh.faces()) {
    const auto vs = mesh.vertices(f);
    const Vec3 fn = (p[vs[1]] - p[vs[0]]).cross(p[vs[2]] - p[vs[0]]);
    for (Vertex v : vs) n[v] += fn;
  }
  for (Vec3& x : n) x.normalize();
  return n;
}

// Per free vertex of `regions`: (x - base) along base's vertex normal.
inline std::vector<double> detail_heights(const Mesh& mesh, const Regions& regions, const VertexData<Vec3>& x,
                                          const VertexData<Vec3>& base) {
  const VertexData<Vec3> n = vertex_normals(mesh, base);
  std::vector<double> h;
  for (Vertex v : regions.free_vertices()) h.push_back((x[v] - base[v]).dot(n[v]));
  return h;
}

// Relative errors |h1 - h0| / |h0| of the tall detail (|h0| above half the largest), sorted.
inline std::vector<double> tall_height_errors(const std::vector<double>& h0, const std::vector<double>& h1) {
  double tallest = 0;
  for (double h : h0) tallest = std::max(tallest, std::abs(h));
  std::vector<double> errors;
  for (std::size_t i = 0; i < h0.size(); ++i)
    if (std::abs(h0[i]) > 0.5 * tallest) errors.push_back(std::abs(h1[i] - h0[i]) / std::abs(h0[i]));
  std::sort(errors.begin(), errors.end());
  return errors;
}

}  // namespace freeform::test
