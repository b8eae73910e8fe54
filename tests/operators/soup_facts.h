// Test helpers that derive facts from a TriangleSoup directly (no Mesh, no operators), so the
// operator tests compare against independent computations.
#pragma once

#include "freeform/mesh/types.h"

#include <algorithm>
#include <map>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace freeform::test {

inline const Vec3& corner(const TriangleSoup& s, const Tri& t, int k) {
  return s.positions[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
}

inline Vec3 face_normal(const TriangleSoup& s, const Tri& t) {
  return (corner(s, t, 1) - corner(s, t, 0)).cross(corner(s, t, 2) - corner(s, t, 0));  // |n| = 2A
}

inline double surface_area(const TriangleSoup& s) {
  double a = 0.0;
  for (const Tri& t : s.faces) a += 0.5 * face_normal(s, t).norm();
  return a;
}

// Directed edge -> number of faces using it, and the undirected edges -> number of faces.
inline std::map<std::pair<int, int>, int> undirected_edges(const TriangleSoup& s) {
  std::map<std::pair<int, int>, int> edges;
  for (const Tri& t : s.faces) {
    for (int k = 0; k < 3; ++k) {
      const auto e = std::minmax(t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]);
      ++edges[{e.first, e.second}];
    }
  }
  return edges;
}

inline std::map<std::pair<int, int>, int> directed_edges(const TriangleSoup& s) {
  std::map<std::pair<int, int>, int> edges;
  for (const Tri& t : s.faces) {
    for (int k = 0; k < 3; ++k) ++edges[{t[static_cast<std::size_t>(k)], t[static_cast<std::size_t>((k + 1) % 3)]}];
  }
  return edges;
}

inline int euler_characteristic(const TriangleSoup& s) {
  return static_cast<int>(s.positions.size()) - static_cast<int>(undirected_edges(s).size()) +
         static_cast<int>(s.faces.size());
}

inline int boundary_edge_count(const TriangleSoup& s) {
  int n = 0;
  for (const auto& [e, count] : undirected_edges(s)) n += count == 1 ? 1 : 0;
  return n;
}

// Vertices on an edge used by one face only.
inline std::vector<bool> boundary_vertices(const TriangleSoup& s) {
  std::vector<bool> b(s.positions.size(), false);
  for (const auto& [e, count] : undirected_edges(s)) {
    if (count == 1) b[static_cast<std::size_t>(e.first)] = b[static_cast<std::size_t>(e.second)] = true;
  }
  return b;
}

inline std::vector<std::set<int>> neighbours(const TriangleSoup& s) {
  std::vector<std::set<int>> nb(s.positions.size());
  for (const auto& [e, count] : undirected_edges(s)) {
    nb[static_cast<std::size_t>(e.first)].insert(e.second);
    nb[static_cast<std::size_t>(e.second)].insert(e.first);
  }
  return nb;
}

// min over faces of 2A / (longest edge)^2 (equilateral: sqrt(3)/2).
inline double min_shape_quality(const TriangleSoup& s) {
  double q = 1e300;
  for (const Tri& t : s.faces) {
    const double l =
        std::max({(corner(s, t, 1) - corner(s, t, 0)).squaredNorm(), (corner(s, t, 2) - corner(s, t, 1)).squaredNorm(),
                  (corner(s, t, 0) - corner(s, t, 2)).squaredNorm()});
    q = std::min(q, face_normal(s, t).norm() / l);
  }
  return q;
}

// Moves every interior vertex of a planar soup by a uniform random offset in
// [-amount, amount]^2 (in the plane). Deterministic for a given seed.
inline void jitter_interior(TriangleSoup& s, double amount, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  const std::vector<bool> boundary = boundary_vertices(s);
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    if (boundary[i]) continue;
    s.positions[i].x() += u(rng);
    s.positions[i].y() += u(rng);
  }
}

}  // namespace freeform::test
