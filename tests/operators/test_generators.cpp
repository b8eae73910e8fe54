// Generators: counts by formula, Euler characteristic, orientation, shape, argument checks.
#include "soup_facts.h"

#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace freeform {
namespace {

constexpr double kPi = std::numbers::pi;

using test::directed_edges;
using test::euler_characteristic;
using test::face_normal;

// Each directed edge used once (consistent orientation, manifold edges), indices in range.
void expect_consistent(const TriangleSoup& s) {
  for (const Tri& t : s.faces) {
    for (int k : t) {
      ASSERT_GE(k, 0);
      ASSERT_LT(k, static_cast<int>(s.positions.size()));
    }
  }
  for (const auto& [e, count] : directed_edges(s)) EXPECT_EQ(count, 1) << e.first << "->" << e.second;
  for (const auto& [e, count] : test::undirected_edges(s)) EXPECT_LE(count, 2);
}

void expect_planar_up(const TriangleSoup& s) {
  for (const Vec3& p : s.positions) EXPECT_EQ(p.z(), 0.0);
  for (const Tri& t : s.faces) {
    const Vec3 n = face_normal(s, t);
    EXPECT_GT(n.z(), 0.0);
    EXPECT_NEAR(n.x(), 0.0, 1e-15);
    EXPECT_NEAR(n.y(), 0.0, 1e-15);
  }
}

TEST(Generators, PlaneCountsEulerOrientation) {
  for (auto [nx, ny] : {std::pair{1, 1}, std::pair{3, 2}, std::pair{7, 11}}) {
    const TriangleSoup s = make_plane(nx, ny, 2.0, 3.0);
    EXPECT_EQ(s.positions.size(), static_cast<std::size_t>((nx + 1) * (ny + 1)));
    EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(2 * nx * ny));
    EXPECT_EQ(euler_characteristic(s), 1);
    EXPECT_EQ(test::boundary_edge_count(s), 2 * (nx + ny));
    expect_consistent(s);
    expect_planar_up(s);
    EXPECT_NEAR(test::surface_area(s), 6.0, 1e-12);
    // Row-major from (0,0).
    EXPECT_EQ(s.positions[1], Vec3(2.0 / nx, 0, 0));
    EXPECT_EQ(s.positions.back(), Vec3(2.0, 3.0, 0));
  }
}

TEST(Generators, DiskCountsEulerOrientationShape) {
  for (int rings : {1, 2, 5, 12}) {
    const double r = 2.5;
    const TriangleSoup s = make_disk(rings, r);
    EXPECT_EQ(s.positions.size(), static_cast<std::size_t>(1 + 3 * rings * (rings + 1)));
    EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(6 * rings * rings));
    EXPECT_EQ(euler_characteristic(s), 1);
    EXPECT_EQ(test::boundary_edge_count(s), 6 * rings);
    expect_consistent(s);
    expect_planar_up(s);
    EXPECT_GT(test::min_shape_quality(s), 0.5);  // near-equilateral (equilateral: 0.866)
    for (const Vec3& p : s.positions) EXPECT_LE(p.norm(), r * (1 + 1e-14));
    // Area tends to pi r^2 from below (inscribed polygon).
    const double a = test::surface_area(s);
    EXPECT_LT(a, kPi * r * r);
    if (rings >= 5) {
      EXPECT_GT(a, 0.97 * kPi * r * r);
    }
  }
}

TEST(Generators, AnnulusCountsEulerOrientationRadii) {
  for (auto [rings, segments] : {std::pair{1, 3}, std::pair{2, 8}, std::pair{5, 40}}) {
    const double ri = 0.5, ro = 2.0;
    const TriangleSoup s = make_annulus(ri, ro, rings, segments);
    EXPECT_EQ(s.positions.size(), static_cast<std::size_t>((rings + 1) * segments));
    EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(2 * rings * segments));
    EXPECT_EQ(euler_characteristic(s), 0);
    EXPECT_EQ(test::boundary_edge_count(s), 2 * segments);
    expect_consistent(s);
    expect_planar_up(s);
    EXPECT_GT(test::min_shape_quality(s), 0.05);
    double rmin = 1e9, rmax = 0;
    for (const Vec3& p : s.positions) {
      rmin = std::min(rmin, p.norm());
      rmax = std::max(rmax, p.norm());
    }
    EXPECT_NEAR(rmin, ri, 1e-14);
    EXPECT_NEAR(rmax, ro, 1e-14);
  }
}

TEST(Generators, IcosphereCountsEulerOutwardRadius) {
  for (int sub = 0; sub <= 4; ++sub) {
    const double r = 1.7;
    const TriangleSoup s = make_icosphere(sub, r);
    const std::size_t p4 = std::size_t{1} << (2 * sub);
    EXPECT_EQ(s.positions.size(), 10 * p4 + 2);
    EXPECT_EQ(s.faces.size(), 20 * p4);
    EXPECT_EQ(euler_characteristic(s), 2);
    EXPECT_EQ(test::boundary_edge_count(s), 0);
    expect_consistent(s);
    for (const Vec3& p : s.positions) EXPECT_NEAR(p.norm(), r, 1e-13);
    for (const Tri& t : s.faces) {
      const Vec3 centroid = (test::corner(s, t, 0) + test::corner(s, t, 1) + test::corner(s, t, 2)) / 3.0;
      EXPECT_GT(face_normal(s, t).normalized().dot(centroid.normalized()), 0.9);
    }
    EXPECT_GT(test::min_shape_quality(s), 0.6);
    EXPECT_LT(test::surface_area(s), 4 * kPi * r * r);
  }
}

TEST(Generators, CylinderCountsEulerOutward) {
  for (auto [rings, segments] : {std::pair{1, 3}, std::pair{4, 7}, std::pair{10, 32}}) {
    const double r = 0.8, h = 2.0;
    const TriangleSoup s = make_cylinder(rings, segments, r, h);
    EXPECT_EQ(s.positions.size(), static_cast<std::size_t>((rings + 1) * segments));
    EXPECT_EQ(s.faces.size(), static_cast<std::size_t>(2 * rings * segments));
    EXPECT_EQ(euler_characteristic(s), 0);
    EXPECT_EQ(test::boundary_edge_count(s), 2 * segments);
    expect_consistent(s);
    for (const Vec3& p : s.positions) {
      EXPECT_NEAR(std::hypot(p.x(), p.y()), r, 1e-14);
      EXPECT_GE(p.z(), 0.0);
      EXPECT_LE(p.z(), h);
    }
    for (const Tri& t : s.faces) {
      Vec3 c = (test::corner(s, t, 0) + test::corner(s, t, 1) + test::corner(s, t, 2)) / 3.0;
      c.z() = 0;
      EXPECT_GT(face_normal(s, t).dot(c), 0.0);
    }
    EXPECT_GT(test::min_shape_quality(s), 0.05);
  }
}

TEST(Generators, BumpyPlaneHeightsAndOrientation) {
  const double amp = 0.05, freq = 2.0;
  const TriangleSoup s = make_bumpy_plane(20, 10, amp, freq, 2.0, 1.0);
  const TriangleSoup flat = make_plane(20, 10, 2.0, 1.0);
  ASSERT_EQ(s.positions.size(), flat.positions.size());
  EXPECT_EQ(s.faces, flat.faces);
  double zmax = 0;
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const Vec3& p = s.positions[i];
    EXPECT_EQ(p.x(), flat.positions[i].x());
    EXPECT_EQ(p.y(), flat.positions[i].y());
    EXPECT_NEAR(p.z(), amp * std::sin(2 * kPi * freq * p.x() / 2.0) * std::sin(2 * kPi * freq * p.y()), 1e-15);
    zmax = std::max(zmax, std::abs(p.z()));
  }
  EXPECT_GT(zmax, 0.9 * amp);
  for (const Tri& t : s.faces) EXPECT_GT(face_normal(s, t).z(), 0.0);
  expect_consistent(s);
}

TEST(Generators, RejectBadArguments) {
  EXPECT_THROW(make_plane(0, 3), InvalidInput);
  EXPECT_THROW(make_plane(3, -1), InvalidInput);
  EXPECT_THROW(make_plane(3, 3, 0.0, 1.0), InvalidInput);
  EXPECT_THROW(make_plane(3, 3, 1.0, NAN), InvalidInput);
  EXPECT_THROW(make_plane(1 << 20, 1 << 20), InvalidInput);
  EXPECT_THROW(make_disk(0), InvalidInput);
  EXPECT_THROW(make_disk(3, -1.0), InvalidInput);
  EXPECT_THROW(make_annulus(1.0, 1.0, 2, 8), InvalidInput);
  EXPECT_THROW(make_annulus(0.0, 1.0, 2, 8), InvalidInput);
  EXPECT_THROW(make_annulus(0.5, 1.0, 0, 8), InvalidInput);
  EXPECT_THROW(make_annulus(0.5, 1.0, 2, 2), InvalidInput);
  EXPECT_THROW(make_icosphere(-1), InvalidInput);
  EXPECT_THROW(make_icosphere(11), InvalidInput);
  EXPECT_THROW(make_icosphere(2, 0.0), InvalidInput);
  EXPECT_THROW(make_cylinder(0, 8), InvalidInput);
  EXPECT_THROW(make_cylinder(2, 2), InvalidInput);
  EXPECT_THROW(make_cylinder(2, 8, 1.0, -1.0), InvalidInput);
  EXPECT_THROW(make_bumpy_plane(0, 4, 0.1, 1.0), InvalidInput);
  EXPECT_THROW(make_bumpy_plane(4, 4, INFINITY, 1.0), InvalidInput);
  EXPECT_THROW(make_bumpy_plane(4, 4, 0.1, -1.0), InvalidInput);
}

}  // namespace
}  // namespace freeform
