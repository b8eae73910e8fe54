// Region operations against closed forms: on a grid whose cells all split along the same
// diagonal, the hop distance between (i, j) and (i + dx, j + dy) is max(|dx|, |dy|) when dx
// and dy have the same sign and |dx| + |dy| otherwise (a hexagonal lattice), so grow/shrink
// are checked against brute force over that formula. The flood is compared with Euclidean
// disks on a flat plane and with selectors.h's geodesic_distance.
#include "editor/region_ops.h"

#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"
#include "freeform/regions/selectors.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

using namespace freeform;
using namespace freeform::editor;

namespace {

constexpr int kN = 20;  // cells per side

// (kN+1)^2 vertices, vertex (i, j) = j (kN+1) + i, every cell split along (i,j)-(i+1,j+1).
Mesh uniform_grid() {
  TriangleSoup s;
  for (int j = 0; j <= kN; ++j)
    for (int i = 0; i <= kN; ++i) s.positions.emplace_back(i, j, 0.0);
  auto id = [](int i, int j) { return j * (kN + 1) + i; };
  for (int j = 0; j < kN; ++j)
    for (int i = 0; i < kN; ++i) {
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return Mesh::from_soup(s);
}

int hop(Vertex a, Vertex b) {
  const int dx = b.idx() % (kN + 1) - a.idx() % (kN + 1), dy = b.idx() / (kN + 1) - a.idx() / (kN + 1);
  return (dx >= 0) == (dy >= 0) ? std::max(std::abs(dx), std::abs(dy)) : std::abs(dx) + std::abs(dy);
}

Vertex at(int i, int j) { return Vertex(j * (kN + 1) + i); }

std::vector<Vertex> where(const Mesh& mesh, const std::function<bool(Vertex)>& pred) {
  std::vector<Vertex> out;
  for (Vertex v : mesh.vertices())
    if (pred(v)) out.push_back(v);
  return out;
}

int min_hop(Vertex v, const std::vector<Vertex>& set) {
  int best = 1 << 20;
  for (Vertex s : set) best = std::min(best, hop(v, s));
  return best;
}

// A blob: an L shape touching the mesh boundary, a lone vertex and a short diagonal bar.
std::vector<Vertex> blob(const Mesh& mesh) {
  std::vector<Vertex> set = where(mesh, [](Vertex v) {
    const int i = v.idx() % (kN + 1), j = v.idx() / (kN + 1);
    return (i <= 7 && j >= 3 && j <= 6) || (i >= 4 && i <= 7 && j >= 3 && j <= 12);
  });
  set.push_back(at(15, 15));
  for (int k = 0; k < 4; ++k) set.push_back(at(12 + k, 3 + k));
  std::sort(set.begin(), set.end());
  return set;
}

}  // namespace

TEST(RegionOps, GrowOfOneVertexIsAHexagonOf3kkPlus1) {
  const Mesh mesh = uniform_grid();
  const std::vector<Vertex> seed{at(10, 10)};
  for (int k = 0; k <= 5; ++k) EXPECT_EQ(static_cast<int>(grow_rings(mesh, seed, k).size()), 3 * k * (k + 1) + 1) << k;
}

TEST(RegionOps, GrowAndShrinkMatchTheHopMetric) {
  const Mesh mesh = uniform_grid();
  const std::vector<Vertex> set = blob(mesh);
  const std::vector<Vertex> outside = where(mesh, [&](Vertex v) { return !std::binary_search(set.begin(), set.end(), v); });
  for (int k = 0; k <= 4; ++k) {
    EXPECT_EQ(grow_rings(mesh, set, k), where(mesh, [&](Vertex v) { return min_hop(v, set) <= k; })) << k;
    // Shrink: only unselected vertices erode, the mesh boundary does not.
    EXPECT_EQ(shrink_rings(mesh, set, k), where(mesh, [&](Vertex v) {
                return std::binary_search(set.begin(), set.end(), v) && min_hop(v, outside) > k;
              })) << k;
  }
  // The L's vertices on the mesh boundary (i = 0) survive one ring of shrinking.
  const std::vector<Vertex> shrunk = shrink_rings(mesh, set, 1);
  EXPECT_TRUE(std::binary_search(shrunk.begin(), shrunk.end(), at(0, 4)));
  EXPECT_FALSE(std::binary_search(shrunk.begin(), shrunk.end(), at(15, 15)));
  const std::vector<Vertex> everything = where(mesh, [](Vertex) { return true; });
  EXPECT_EQ(shrink_rings(mesh, everything, 3), everything);
  // Unsorted input with repeats gives the same answers.
  std::vector<Vertex> messy = set;
  messy.insert(messy.end(), set.begin(), set.begin() + 5);
  std::reverse(messy.begin(), messy.end());
  EXPECT_EQ(grow_rings(mesh, messy, 2), grow_rings(mesh, set, 2));
  EXPECT_EQ(shrink_rings(mesh, messy, 2), shrink_rings(mesh, set, 2));
}

TEST(RegionOps, ClosingAndOpeningOfDiskLikeSets) {
  const Mesh mesh = uniform_grid();
  // A hop ball far from the boundary is closed: shrink(grow(S)) == S; opening it too.
  const std::vector<Vertex> ball = grow_rings(mesh, std::vector<Vertex>{at(10, 10)}, 4);
  for (int k = 1; k <= 3; ++k) {
    EXPECT_EQ(shrink_rings(mesh, grow_rings(mesh, ball, k), k), ball) << k;
    EXPECT_EQ(grow_rings(mesh, shrink_rings(mesh, ball, k), k), ball) << k;
  }
  // A Euclidean disk: closing contains it, opening is contained in it.
  const std::vector<Vertex> disk = where(mesh, [](Vertex v) {
    const double x = v.idx() % (kN + 1) - 9.7, y = v.idx() / (kN + 1) - 10.2;
    return x * x + y * y <= 5.3 * 5.3;
  });
  for (int k = 1; k <= 3; ++k) {
    const std::vector<Vertex> closed = shrink_rings(mesh, grow_rings(mesh, disk, k), k);
    const std::vector<Vertex> opened = grow_rings(mesh, shrink_rings(mesh, disk, k), k);
    EXPECT_TRUE(std::includes(closed.begin(), closed.end(), disk.begin(), disk.end())) << k;
    EXPECT_TRUE(std::includes(disk.begin(), disk.end(), opened.begin(), opened.end())) << k;
    EXPECT_FALSE(opened.empty());
  }
}

TEST(RegionOps, GeodesicFloodOnAFlatPlaneIsBetweenEuclideanDisks) {
  const Mesh mesh = Mesh::from_soup(make_plane(40, 40));  // alternating diagonals, spacing 1/40
  const Vertex seed(20 * 41 + 20);                          // (0.5, 0.5)
  const Vec3 c = mesh.position(seed);
  for (double r : {0.05, 0.17, 0.3, 0.45}) {
    const std::vector<Vertex> flood = geodesic_flood(mesh, mesh.positions(), seed, r);
    const auto dist = geodesic_distance(mesh, seed);
    EXPECT_EQ(flood, where(mesh, [&](Vertex v) { return dist[v] <= r; })) << r;
    for (Vertex v : mesh.vertices()) {
      const double e = (mesh.position(v) - c).norm();
      const bool in = std::binary_search(flood.begin(), flood.end(), v);
      if (e <= r / 1.08) {
        EXPECT_TRUE(in) << "r " << r << " vertex " << v.idx();
      }
      if (in) {
        EXPECT_LE(e, r + 1e-12) << "r " << r << " vertex " << v.idx();
      }
    }
  }
  // The flood measures the positions it is given (the displayed geometry), not mesh.positions().
  VertexData<Vec3> doubled = mesh.positions();
  for (Vec3& p : doubled) p *= 2.0;
  EXPECT_EQ(geodesic_flood(mesh, doubled, seed, 0.6), geodesic_flood(mesh, mesh.positions(), seed, 0.3));
  EXPECT_LT(geodesic_flood(mesh, doubled, seed, 0.3).size(), geodesic_flood(mesh, mesh.positions(), seed, 0.3).size());
  EXPECT_EQ(geodesic_flood(mesh, mesh.positions(), seed, 0.0), std::vector<Vertex>{seed});
  EXPECT_THROW(geodesic_flood(mesh, mesh.positions(), seed, -1.0), InvalidInput);
  EXPECT_THROW(geodesic_flood(mesh, mesh.positions(), Vertex(41 * 41), 1.0), InvalidInput);
  EXPECT_THROW(geodesic_flood(mesh, VertexData<Vec3>(3, Vec3::Zero()), seed, 1.0), InvalidInput);
}

TEST(RegionOps, ComponentsOfARegionMatchUnionFind) {
  const Mesh mesh = uniform_grid();
  const std::vector<Vertex> set = blob(mesh);
  // Union-find over the mesh edges whose both ends are in the set.
  std::vector<int> parent(static_cast<std::size_t>(mesh.n_vertices()));
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int i) { return parent[i] == i ? i : parent[i] = root(parent[i]); };
  auto in = [&](Vertex v) { return std::binary_search(set.begin(), set.end(), v); };
  for (Edge e : mesh.edges()) {
    const Vertex a = mesh.to_vertex(mesh.halfedge(e, 0)), b = mesh.to_vertex(mesh.halfedge(e, 1));
    if (in(a) && in(b)) parent[root(a.idx())] = root(b.idx());
  }
  const auto pieces = region_components(mesh, set);
  // The L, the lone vertex and the diagonal bar (its steps follow the cell diagonals).
  ASSERT_EQ(pieces.size(), 3u);
  std::size_t total = 0;
  for (const auto& piece : pieces) {
    total += piece.size();
    EXPECT_TRUE(std::is_sorted(piece.begin(), piece.end()));
    for (Vertex v : piece) EXPECT_EQ(root(v.idx()), root(piece.front().idx()));
  }
  EXPECT_EQ(total, set.size());
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    EXPECT_LT(pieces[i - 1].front(), pieces[i].front());
    EXPECT_NE(root(pieces[i - 1].front().idx()), root(pieces[i].front().idx()));
  }
  EXPECT_EQ(pieces[2], (std::vector<Vertex>{at(15, 15)}));
  EXPECT_TRUE(region_components(mesh, std::vector<Vertex>{}).empty());
  EXPECT_THROW(grow_rings(mesh, std::vector<Vertex>{Vertex(-1)}, 1), InvalidInput);
  EXPECT_THROW(shrink_rings(mesh, set, -1), InvalidInput);
}
