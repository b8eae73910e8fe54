// The foot-point shape's verdicts on open boundaries (multires/operator_shape.h): the membrane
// fill's boundary is free where the support reaches a hole of the mesh. On a flat sheet it stays
// on the sheet; past a tube's last constrained ring it leaves the tube: harmonic with its far
// edge free, it keeps that ring's height and contracts (in the tube's conformal chart the
// radius falls as cosh(h - t) / cosh(h), t the distance past the ring, h the free length).
#include "freeform/multires/operator_shape.h"

#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace freeform;

namespace {

// Support: coordinate `axis` at least support_from; one movable handle: it within [handle_lo, handle_hi].
Regions bands(const Mesh& mesh, int axis, double support_from, double handle_lo, double handle_hi) {
  std::vector<Vertex> support;
  HandleRegion handle;
  for (Vertex v : mesh.vertices()) {
    const double c = mesh.position(v)[axis];
    if (c >= support_from) support.push_back(v);
    if (c >= handle_lo && c <= handle_hi) handle.vertices.push_back(v);
  }
  return Regions(mesh, support, {handle});
}

BcmSettings order(int k) {
  BcmSettings s;
  s.order = k;
  return s;
}

}  // namespace

TEST(OperatorShape, OpenTubeEndIsLifted) {
  // Radius 1, z in [0, 4], 40 rings of 24: fixed below z = 1, the handle the rings at z in
  // [2, 2.2], the free end above them 1.8 long: its fill is an annulus at the handle's height,
  // so every vertex of the top ring lies about 1.8 off the fill along its normal, several times
  // its edges' mean length (about 0.2).
  const Mesh tube = Mesh::from_soup(make_cylinder(40, 24, 1.0, 4.0));
  const OperatorShape shape = base_operator_shape(tube, bands(tube, 2, 1.0, 2.0, 2.2), order(2));
  EXPECT_EQ(shape.lifted_boundary, 24);
}

TEST(OperatorShape, FlatSheetSidesAreNotLifted) {
  // A strip fixed at one end, its handle the other: the support spans the width and reaches
  // both long sides, and the fill, with every constraint in the plane, stays in it.
  const Mesh plane = Mesh::from_soup(make_plane(60, 12, 5.0, 1.0));
  const Regions regions = bands(plane, 0, 1.0, 4.5, 5.0);
  int on_sides = 0;
  for (Vertex v : regions.free_vertices()) on_sides += plane.is_boundary(v);
  ASSERT_GT(on_sides, 20);
  const OperatorShape shape = base_operator_shape(plane, regions, order(2));
  EXPECT_EQ(shape.lifted_boundary, 0);
  EXPECT_EQ(shape.overhanging, 0);
  EXPECT_FALSE(shape.positions.raw().empty()) << shape.fallback;
}
