// Planar annulus set-ups for the closed-form and smoothness references (docs/references.md).
// make_annulus stores circle i (radius r_in * q^i) as vertices [i * segments, (i+1) * segments).
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "freeform/regions/regions.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <vector>

namespace freeform::test {

struct Annulus {
  double r_inner = 0.25, r_outer = 1.0;
  int rings = 0, segments = 0;
  Mesh mesh;

  // Near-equilateral triangles: q = r_{i+1} / r_i ~ 1 + sqrt(3) pi / segments.
  Annulus(double r_in, double r_out, int segments_) : r_inner(r_in), r_outer(r_out), segments(segments_) {
    const double q = 1.0 + std::sqrt(3.0) * std::numbers::pi / segments;
    rings = static_cast<int>(std::lround(std::log(r_out / r_in) / std::log(q)));
    mesh = Mesh::from_soup(make_annulus(r_in, r_out, rings, segments));
  }
  double radius(int circle) const { return r_inner * std::pow(r_outer / r_inner, static_cast<double>(circle) / rings); }
  int circle_of(Vertex v) const { return v.idx() / segments; }
  std::vector<Vertex> circles(int first, int last) const {  // inclusive
    std::vector<Vertex> out;
    for (int i = first * segments; i < (last + 1) * segments; ++i) out.emplace_back(i);
    return out;
  }
};

// Handle = circles 0..k-1 lifted by h in z, support = circles 0..last_free, everything outside
// fixed. Returns all positions after the edit.
inline VertexData<Vec3> lift_inner_disk(const Annulus& a, int k, int last_free, double h, double outer_c,
                                        int* n_free = nullptr) {
  const Regions regions(a.mesh, a.circles(0, last_free), {HandleRegion{a.circles(0, k - 1), true}});
  BcmSettings settings;
  settings.order = k;
  settings.smoothness.outer = outer_c;
  const BcmSolver solver(a.mesh, regions, settings);
  const Eigen::Affine3d lift(Eigen::Translation3d(0, 0, h));
  VertexData<Vec3> x = a.mesh.positions();
  solver.evaluate(std::span<const Eigen::Affine3d>(&lift, 1), x);
  if (n_free) *n_free = solver.n_free();
  return x;
}

}  // namespace freeform::test
