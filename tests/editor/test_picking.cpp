// ScreenPicker against independent truth: a pinhole projection written here, front-facing
// incident faces on a convex sphere, the analytic shadow of a square on a parallel plane,
// winding-number point-in-polygon, and analytic ray/plane hits. Plus timings on 250k triangles.
#include "editor/picking.h"

#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>

using namespace freeform;
using namespace freeform::editor;

namespace {

constexpr int kW = 640, kH = 480;

ScreenView make_view(const Vec3& eye, const Vec3& target, const Vec3& up, double fov = 30.0) {
  ScreenView view;
  view.camera.eye = eye;
  view.camera.target = target;
  view.camera.up = up;
  view.camera.fov_y_deg = fov;
  view.width = kW;
  view.height = kH;
  return view;
}

// Pinhole projection from the camera frame (no matrices): focal length in pixels f = (H/2) /
// tan(fov/2); x right, y down from the top-left corner.
struct Pinhole {
  Vec3 eye, s, u, f;
  double focal;
  explicit Pinhole(const ScreenView& v) : eye(v.camera.eye) {
    f = (v.camera.target - eye).normalized();
    s = f.cross(v.camera.up).normalized();
    u = s.cross(f);
    focal = 0.5 * v.height / std::tan(0.5 * v.camera.fov_y_deg * std::numbers::pi / 180.0);
  }
  Eigen::Vector2d operator()(const Vec3& p) const {
    const Vec3 d = p - eye;
    return {0.5 * kW + focal * d.dot(s) / d.dot(f), 0.5 * kH - focal * d.dot(u) / d.dot(f)};
  }
  // Distance (px) from the viewport border, negative outside.
  static double inside_margin(const Eigen::Vector2d& q) { return std::min({q.x(), q.y(), kW - q.x(), kH - q.y()}); }
};

Mesh merge(const TriangleSoup& a, const TriangleSoup& b) {
  TriangleSoup s = a;
  const int off = static_cast<int>(a.positions.size());
  s.positions.insert(s.positions.end(), b.positions.begin(), b.positions.end());
  for (Tri t : b.faces) s.faces.push_back({t[0] + off, t[1] + off, t[2] + off});
  return Mesh::from_soup(s);
}

TriangleSoup square(int n, double half, double z) {  // [-half, half]^2 at height z, normal +z
  TriangleSoup s = make_plane(n, n, 2 * half, 2 * half);
  for (Vec3& p : s.positions) p += Vec3(-half, -half, z);
  return s;
}

// Winding number of a closed polygon around p (independent of the picker's crossing test).
int winding(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& poly) {
  double angle = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Eigen::Vector2d a = poly[i] - p, b = poly[(i + 1) % poly.size()] - p;
    angle += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  return static_cast<int>(std::lround(angle / (2 * std::numbers::pi)));
}

double segment_distance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return (a + t * (b - a) - p).norm();
}

}  // namespace

TEST(Picking, BrushOnAConvexSphereSelectsFrontFacingVerticesInTheCircle) {
  const Mesh mesh = Mesh::from_soup(make_icosphere(4, 1.0));
  const Bvh bvh(mesh, mesh.positions());
  const ScreenView view = make_view(Vec3(0.9, -4.5, 1.4), Vec3(0.05, 0.1, -0.05), Vec3(0, 0, 1));
  const ScreenPicker picker(mesh, mesh.positions(), bvh, view);
  const Pinhole proj(view);
  const Eigen::Vector2d centre_of_sphere = proj(Vec3::Zero());
  // Covering the whole sphere, then a circle straddling the silhouette.
  const std::vector<std::pair<Eigen::Vector2d, double>> brushes = {{centre_of_sphere, 400.0},
                                                                  {centre_of_sphere + Eigen::Vector2d(150, -60), 70.0}};
  for (const auto& [centre, radius] : brushes) {
    const std::vector<Vertex> got = picker.brush(centre, radius);
    int compared = 0, excluded = 0, expected_count = 0;
    for (Vertex v : mesh.vertices()) {
      const Vec3& p = mesh.position(v);
      const Eigen::Vector2d q = proj(p);
      // Visible on a convex closed mesh <=> some incident face faces the eye.
      double facing = -1.0;
      for (Halfedge h : mesh.outgoing(v)) {
        if (mesh.is_boundary(h)) continue;
        const auto vs = mesh.vertices(mesh.face(h));
        const Vec3 n = (mesh.position(vs[1]) - mesh.position(vs[0])).cross(mesh.position(vs[2]) - mesh.position(vs[0]));
        facing = std::max(facing, n.normalized().dot((view.camera.eye - p).normalized()));
      }
      if (std::abs(facing) < 1e-6 || std::abs((q - centre).norm() - radius) < 1e-6) {
        ++excluded;
        continue;
      }
      const bool expected = facing > 0 && (q - centre).norm() < radius && Pinhole::inside_margin(q) > 0;
      const bool selected = std::binary_search(got.begin(), got.end(), v);
      ++compared;
      expected_count += expected;
      EXPECT_EQ(selected, expected) << "vertex " << v.idx() << " facing " << facing;
      EXPECT_EQ(picker.visible(v), facing > 0 && Pinhole::inside_margin(q) > 0) << "vertex " << v.idx();
    }
    EXPECT_LE(excluded, 2);
    EXPECT_GT(expected_count, 100);
    EXPECT_TRUE(std::is_sorted(got.begin(), got.end()));
    EXPECT_EQ(std::adjacent_find(got.begin(), got.end()), got.end());
  }
}

TEST(Picking, BrushSeesTheBackPlaneExceptTheShadowOfTheFrontSquare) {
  // Front square [-0.5, 0.5]^2 at z = 1, back square [-2, 2]^2 at z = 0 (spacing 0.1), eye at
  // height 5: a back vertex q is hidden iff the eye->q segment crosses z = 1 inside the front
  // square, at 0.2 eye + 0.8 q. The eye offset keeps every grid vertex off the shadow border.
  const TriangleSoup front = square(10, 0.5, 1.0), back = square(40, 2.0, 0.0);
  const Mesh mesh = merge(front, back);
  const int n_front = static_cast<int>(front.positions.size());
  const Bvh bvh(mesh, mesh.positions());
  const ScreenView view = make_view(Vec3(0.05, 0.13, 5.0), Vec3(0, 0, 0), Vec3(0, 1, 0));
  const ScreenPicker picker(mesh, mesh.positions(), bvh, view);
  const Pinhole proj(view);
  const std::vector<std::pair<Eigen::Vector2d, double>> brushes = {{{320, 240}, 1e4}, {{300, 200}, 95.0}};
  for (const auto& [centre, radius] : brushes) {
    const std::vector<Vertex> got = picker.brush(centre, radius);
    int hidden_in_circle = 0, front_in_circle = 0, expected_count = 0;
    for (Vertex v : mesh.vertices()) {
      const Vec3& p = mesh.position(v);
      const Eigen::Vector2d q = proj(p);
      const bool in_circle = (q - centre).norm() <= radius && Pinhole::inside_margin(q) > 0;
      ASSERT_GT(std::abs((q - centre).norm() - radius), 1e-6);
      ASSERT_GT(std::abs(Pinhole::inside_margin(q)), 1e-6);
      bool hidden = false;
      if (v.idx() >= n_front) {
        const Vec3 s = 0.2 * view.camera.eye + 0.8 * p;
        ASSERT_GT(std::abs(std::max(std::abs(s.x()), std::abs(s.y())) - 0.5), 1e-6);
        hidden = std::abs(s.x()) < 0.5 && std::abs(s.y()) < 0.5;
      } else {
        front_in_circle += in_circle;
      }
      hidden_in_circle += hidden && in_circle;
      expected_count += in_circle && !hidden;
      EXPECT_EQ(std::binary_search(got.begin(), got.end(), v), in_circle && !hidden) << "vertex " << v.idx();
    }
    EXPECT_EQ(static_cast<int>(got.size()), expected_count);
    EXPECT_GT(hidden_in_circle, 20);
    EXPECT_GT(front_in_circle, 20);
  }
}

TEST(Picking, LassoSelectsExactlyTheVerticesInsideTheProjectedPolygon) {
  // A plane facing an oblique camera (perspective distortion), every vertex visible.
  TriangleSoup plane = square(30, 1.0, 0.0);
  const Mesh mesh = Mesh::from_soup(plane);
  const Bvh bvh(mesh, mesh.positions());
  const ScreenView view = make_view(Vec3(0.6, -1.2, 3.5), Vec3(0.1, 0.0, 0.0), Vec3(0, 0, 1), 40.0);
  const ScreenPicker picker(mesh, mesh.positions(), bvh, view);
  const Pinhole proj(view);
  const std::vector<std::vector<Eigen::Vector2d>> polygons = {
      {{200.3, 100.1}, {470.7, 180.2}, {260.9, 400.4}},                                             // triangle
      {{150.2, 90.7}, {500.1, 95.3}, {480.6, 390.2}, {330.4, 200.8}, {160.9, 380.5}},               // concave
      {{320.5, 60.2}, {420.3, 380.1}, {150.7, 170.6}, {490.2, 170.3}, {220.8, 380.9}},              // pentagram
  };
  for (const auto& poly : polygons) {
    const std::vector<Vertex> got = picker.lasso(poly);
    int expected_count = 0, inside_odd_winding_2 = 0;
    for (Vertex v : mesh.vertices()) {
      const Eigen::Vector2d q = proj(mesh.position(v));
      for (std::size_t i = 0; i < poly.size(); ++i)
        ASSERT_GT(segment_distance(q, poly[i], poly[(i + 1) % poly.size()]), 1e-6);
      const int w = winding(q, poly);
      const bool expected = std::abs(w) % 2 == 1;  // even-odd rule
      inside_odd_winding_2 += std::abs(w) == 2;
      expected_count += expected;
      EXPECT_EQ(std::binary_search(got.begin(), got.end(), v), expected) << "vertex " << v.idx();
    }
    EXPECT_EQ(static_cast<int>(got.size()), expected_count);
    EXPECT_GT(expected_count, 50);
    if (&poly == &polygons.back()) {
      EXPECT_GT(inside_odd_winding_2, 10);  // the star's core is out
    }
  }
  EXPECT_TRUE(picker.lasso(std::vector<Eigen::Vector2d>{{0, 0}, {600, 400}}).empty());
}

TEST(Picking, PickHitsTheFaceUnderThePixel) {
  // Plane [0,4]^2 (unit cells) below a camera looking straight down, a small square in front.
  TriangleSoup ground = make_plane(4, 4, 4.0, 4.0);
  TriangleSoup lid = square(1, 0.25, 1.0);
  for (Vec3& p : lid.positions) p += Vec3(2.0, 3.0, 0.0);  // [1.75, 2.25] x [2.75, 3.25] at z = 1
  const Mesh mesh = merge(ground, lid);
  const Bvh bvh(mesh, mesh.positions());
  const ScreenView view = make_view(Vec3(1.3, 2.6, 5.0), Vec3(1.3, 2.6, 0.0), Vec3(0, 1, 0));
  const ScreenPicker picker(mesh, mesh.positions(), bvh, view);
  const Pinhole proj(view);
  for (const Vec3& target : {Vec3(1.3, 2.6, 0.0), Vec3(0.21, 3.35, 0.0), Vec3(2.35, 1.55, 0.0), Vec3(2.1, 2.9, 1.0)}) {
    const Eigen::Vector2d px = proj(target);
    const auto hit = picker.pick(px);
    ASSERT_TRUE(hit.has_value()) << target.transpose();
    EXPECT_LT((hit->point - target).norm(), 1e-9);
    EXPECT_NEAR(hit->distance, (target - view.camera.eye).norm(), 1e-9);
    // The face containing the target (2D test in the plane of its height).
    int containing = -1;
    for (Face f : mesh.faces()) {
      const auto vs = mesh.vertices(f);
      if (std::abs(mesh.position(vs[0]).z() - target.z()) > 1e-12) continue;
      bool in = true;
      for (int k = 0; k < 3; ++k) {
        const Vec3 a = mesh.position(vs[k]), b = mesh.position(vs[(k + 1) % 3]);
        in = in && (b - a).cross(target - a).z() > 0;
      }
      if (in) containing = f.idx();
    }
    EXPECT_EQ(hit->face.idx(), containing);
    Vertex nearest;
    for (Vertex v : mesh.vertices(hit->face))
      if (!nearest.is_valid() || (mesh.position(v) - target).norm() < (mesh.position(nearest) - target).norm()) nearest = v;
    EXPECT_EQ(hit->vertex, nearest);
  }
  // The lid hides the ground below it; off the ground is background; outside the viewport nothing.
  const auto on_lid = picker.pick(proj(Vec3(2.175, 3.1, 0.0)));  // seen through (2.0, 3.0, 1.0)
  ASSERT_TRUE(on_lid.has_value());
  EXPECT_LT((on_lid->point - Vec3(2.0, 3.0, 1.0)).norm(), 1e-9);
  const Eigen::Vector2d off = proj(Vec3(-0.3, 2.6, 0.0));
  ASSERT_GT(Pinhole::inside_margin(off), 0);
  EXPECT_FALSE(picker.pick(off).has_value());
  EXPECT_FALSE(picker.pick(Eigen::Vector2d(-1, 100)).has_value());
  EXPECT_FALSE(picker.pick(Eigen::Vector2d(100, kH + 1)).has_value());
}

TEST(Picking, VerticesBehindTheEyeOrOffScreenAreNotVisible) {
  const Mesh mesh = Mesh::from_soup(square(4, 2.0, 0.0));  // vertices 2 apart... spacing 1
  const Bvh bvh(mesh, mesh.positions());
  // Eye inside the plane's extent, looking along +x just above it: half the plane is behind.
  const ScreenView view = make_view(Vec3(0.0, 0.0, 0.5), Vec3(5.0, 0.0, 0.0), Vec3(0, 0, 1), 60.0);
  const ScreenPicker picker(mesh, mesh.positions(), bvh, view);
  for (Vertex v : mesh.vertices()) {
    const Vec3& p = mesh.position(v);
    if (p.x() <= 0.0) {
      EXPECT_FALSE(picker.visible(v)) << p.transpose();
      if (p.x() < 0.0) {
        EXPECT_FALSE(picker.pixel(v).has_value());
      }
    }
  }
  EXPECT_TRUE(picker.visible(Vertex(5 * 2 + 4)));  // (2, 0, 0): straight ahead
  EXPECT_THROW(picker.visible(Vertex(25)), InvalidInput);
  EXPECT_THROW(picker.brush(Eigen::Vector2d(0, 0), -1.0), InvalidInput);
}

TEST(Picking, TimingOfABrushOnA250kTriangleMesh) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(354, 354, 0.05, 4.0));
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  const Bvh bvh(mesh, mesh.positions());
  const ScreenView view = make_view(Vec3(0.5, -0.9, 0.9), Vec3(0.5, 0.5, 0.0), Vec3(0, 0, 1), 50.0);
  auto t0 = Clock::now();
  const ScreenPicker picker(mesh, mesh.positions(), bvh, view);
  const double construct = ms(Clock::now() - t0);
  // A radius enclosing ~5000 projected vertices around the screen centre.
  const Eigen::Vector2d centre(0.5 * kW, 0.5 * kH);
  std::vector<double> d;
  for (Vertex v : mesh.vertices())
    if (auto q = picker.pixel(v)) d.push_back((*q - centre).norm());
  std::nth_element(d.begin(), d.begin() + 5000, d.end());
  const double radius = d[5000];
  t0 = Clock::now();
  const std::vector<Vertex> cold = picker.brush(centre, radius);
  const double first = ms(Clock::now() - t0);
  t0 = Clock::now();
  const std::vector<Vertex> warm = picker.brush(centre + Eigen::Vector2d(3, 0), radius);
  const double second = ms(Clock::now() - t0);
  t0 = Clock::now();
  int hits = 0;
  for (int i = 0; i < 1000; ++i) hits += picker.pick(Eigen::Vector2d(200 + 0.2 * i, 200 + 0.1 * i)).has_value();
  const double pick_us = ms(Clock::now() - t0);
  std::cout << "[timing] picker on " << mesh.n_faces() << " triangles: construct " << construct << " ms, brush of "
            << cold.size() << " visible vertices (radius " << radius << " px) " << first << " ms cold, " << second
            << " ms after a 3 px move; pick " << pick_us << " us\n";
  EXPECT_GT(cold.size(), 3000u);
  EXPECT_EQ(hits, 1000);
}
