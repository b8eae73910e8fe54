// Folded edges (mesh/folds.h) against closed forms: a flat grid folded about one grid line by a
// known angle has exactly the edges of that line folded by that angle.
#include "freeform/common/error.h"
#include "freeform/mesh/folds.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

using namespace freeform;

namespace {

// A 10 x 10 grid on the unit square folded about x = 0.5: the half x > 0.5 rotated by `degrees`
// about that line (a dihedral of exactly `degrees` along its 10 edges, 0 elsewhere).
VertexData<Vec3> folded(const Mesh& mesh, double degrees) {
  VertexData<Vec3> p = mesh.positions();
  const double a = degrees * std::numbers::pi / 180.0;
  for (Vertex v : mesh.vertices()) {
    const double x = p[v].x() - 0.5;
    if (x > 0) p[v] = Vec3(0.5 + x * std::cos(a), p[v].y(), x * std::sin(a));
  }
  return p;
}

}  // namespace

TEST(Folds, CountsTheEdgesOfAFoldLineByTheirAngle) {
  const Mesh mesh = Mesh::from_soup(make_plane(10, 10));
  EXPECT_EQ(count_folded_edges(mesh, mesh.positions(), mesh.positions()), 0);
  EXPECT_EQ(count_folded_edges(mesh, mesh.positions(), folded(mesh, 59.0)), 0);
  EXPECT_EQ(count_folded_edges(mesh, mesh.positions(), folded(mesh, 61.0)), 10);  // the 10 edges on x = 0.5
  EXPECT_EQ(count_folded_edges(mesh, mesh.positions(), folded(mesh, 61.0), 70.0), 0);
  EXPECT_EQ(count_folded_edges(mesh, mesh.positions(), folded(mesh, 179.0)), 10);
  // Only the growth counts: folded at rest and folded the same after is no fold.
  EXPECT_EQ(count_folded_edges(mesh, folded(mesh, 120.0), folded(mesh, 120.0)), 0);
  // A rigid motion folds nothing.
  VertexData<Vec3> moved = mesh.positions();
  const Eigen::AngleAxisd r(1.0, Vec3(1, 2, 3).normalized());
  for (Vertex v : mesh.vertices()) moved[v] = r * moved[v] + Vec3(3, -1, 2);
  EXPECT_EQ(count_folded_edges(mesh, mesh.positions(), moved), 0);
}

TEST(Folds, WatchesOnlyEdgesAMovingVertexCanChangeAndCountsCollapsedFaces) {
  const Mesh mesh = Mesh::from_soup(make_plane(10, 10));
  // Moving only vertex 5 (on the boundary y = 0): the edges of its faces are watched.
  const Vertex moving[] = {Vertex(5)};
  const FoldCounter counter(mesh, mesh.positions(), moving);
  EXPECT_GT(counter.n_watched(), 0);
  EXPECT_LT(counter.n_watched(), 20);
  VertexData<Vec3> p = mesh.positions();
  p[Vertex(5)] = p[Vertex(16)];  // onto its neighbour: its faces with 16 collapse
  EXPECT_GT(counter.count(p), 0);
  EXPECT_THROW((void)counter.count(VertexData<Vec3>(3, Vec3::Zero())), InvalidInput);
}
