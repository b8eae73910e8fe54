// Small hand-made soups whose topology is known by construction.
#pragma once

#include "freeform/mesh/types.h"

#include <cmath>
#include <numbers>

namespace freeform::test {

inline TriangleSoup tetrahedron() {
  return {{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}

// Zigzag strip: vertices 0..n-1 alternate between y = 0 and y = 1, triangles (i, i+1, i+2)
// oriented consistently. Vertex i neighbours i +- 1 and i +- 2.
inline TriangleSoup strip(int n) {
  TriangleSoup s;
  for (int i = 0; i < n; ++i) s.positions.emplace_back(0.5 * i, i % 2, 0.0);
  for (int i = 0; i + 2 < n; ++i) s.faces.push_back(i % 2 == 0 ? Tri{i, i + 1, i + 2} : Tri{i, i + 2, i + 1});
  return s;
}

// Torus grid with n x m quads (wrapping both ways), split into triangles: genus 1, no boundary.
inline TriangleSoup torus(int n, int m) {
  TriangleSoup s;
  const double two_pi = 2 * std::numbers::pi;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = two_pi * i / n, v = two_pi * j / m;
      s.positions.emplace_back((2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v));
    }
  auto id = [&](int i, int j) { return (i % n) * m + (j % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      s.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

// Cylinder-like annulus grid: `segments` around, `rings`+1 circles: two boundary loops.
inline TriangleSoup annulus_grid(int rings, int segments) {
  TriangleSoup s;
  const double two_pi = 2 * std::numbers::pi;
  for (int r = 0; r <= rings; ++r)
    for (int k = 0; k < segments; ++k)
      s.positions.emplace_back((1.0 + r) * std::cos(two_pi * k / segments), (1.0 + r) * std::sin(two_pi * k / segments), 0);
  auto id = [&](int r, int k) { return r * segments + k % segments; };
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < segments; ++k) {
      s.faces.push_back({id(r, k), id(r + 1, k), id(r + 1, k + 1)});
      s.faces.push_back({id(r, k), id(r + 1, k + 1), id(r, k + 1)});
    }
  return s;
}

}  // namespace freeform::test
