// Bvh ray casts against brute force over every triangle (an independent plane/edge-sign
// intersection), refit against a rebuild, grid-aligned rays, and build/refit timings.
#include "editor/bvh.h"

#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"
#include "freeform/mesh/mesh.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <iostream>
#include <optional>
#include <random>

using namespace freeform;
using namespace freeform::editor;

namespace {

struct Truth {
  int face = -1;
  double t = 0.0;
};

// Closest hit with t in (0, t_max) by intersecting each triangle's plane and testing the
// point against the three edges (a different formula from the Bvh's Möller–Trumbore).
Truth brute_force(const Mesh& mesh, const VertexData<Vec3>& x, const Ray& ray, double t_max = INFINITY,
                  Vertex ignore = Vertex()) {
  Truth best{-1, t_max};
  for (Face f : mesh.faces()) {
    const auto vs = mesh.vertices(f);
    if (vs[0] == ignore || vs[1] == ignore || vs[2] == ignore) continue;
    const Vec3 &a = x[vs[0]], &b = x[vs[1]], &c = x[vs[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double denom = n.dot(ray.direction);
    if (std::abs(denom) < 1e-9 * n.norm() * ray.direction.norm()) continue;
    const double t = n.dot(a - ray.origin) / denom;
    if (!(t > 0.0 && t < best.t)) continue;
    const Vec3 p = ray.origin + t * ray.direction;
    if ((b - a).cross(p - a).dot(n) >= 0 && (c - b).cross(p - b).dot(n) >= 0 && (a - c).cross(p - c).dot(n) >= 0)
      best = {f.idx(), t};
  }
  return best;
}

Vec3 random_in(std::mt19937& rng, const Vec3& lo, const Vec3& hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo);
}

// Rays from random points around the mesh towards random points of a box a bit larger than
// it, so some miss. Checks closest hit, t_max and occluded() against brute force.
void check_random_rays(const Mesh& mesh, const VertexData<Vec3>& x, const Bvh& bvh, const Vec3& lo, const Vec3& hi,
                       const Vec3& origin_lo, const Vec3& origin_hi, int n_rays, unsigned seed, int min_misses) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> pick_vertex(0, mesh.n_vertices() - 1);
  int hits = 0, misses = 0;
  for (int r = 0; r < n_rays; ++r) {
    const Vec3 o = random_in(rng, origin_lo, origin_hi);
    const Vec3 target = random_in(rng, lo, hi);
    const Ray ray{o, (r % 2 ? 1.0 : 3.7) * (target - o).normalized()};  // also non-unit directions
    const Truth truth = brute_force(mesh, x, ray);
    const std::optional<RayHit> hit = bvh.intersect(ray);
    ASSERT_EQ(hit.has_value(), truth.face >= 0) << "ray " << r;
    if (!hit) {
      ++misses;
      EXPECT_FALSE(bvh.occluded(ray, INFINITY));
      continue;
    }
    ++hits;
    EXPECT_EQ(hit->face.idx(), truth.face) << "ray " << r;
    EXPECT_NEAR(hit->t, truth.t, 1e-12 * truth.t) << "ray " << r;
    const auto vs = mesh.vertices(hit->face);
    const Vec3 from_bary = hit->barycentric[0] * x[vs[0]] + hit->barycentric[1] * x[vs[1]] + hit->barycentric[2] * x[vs[2]];
    EXPECT_LT((from_bary - (ray.origin + hit->t * ray.direction)).norm(), 1e-9);
    EXPECT_GE(hit->barycentric.minCoeff(), -1e-12);
    EXPECT_FALSE(bvh.intersect(ray, truth.t * (1 - 1e-9)).has_value());
    EXPECT_TRUE(bvh.occluded(ray, truth.t * (1 + 1e-9)));
    EXPECT_FALSE(bvh.occluded(ray, truth.t * (1 - 1e-9)));
    // Any-hit while ignoring a vertex: compare with brute force ignoring the same vertex.
    const Vertex ignore = r % 3 == 0 ? vs[r % 3] : Vertex(pick_vertex(rng));
    const double limit = truth.t * 2.0;
    EXPECT_EQ(bvh.occluded(ray, limit, ignore), brute_force(mesh, x, ray, limit, ignore).face >= 0) << "ray " << r;
  }
  EXPECT_GT(hits, n_rays / 5);
  EXPECT_GE(misses, min_misses);
}

}  // namespace

TEST(Bvh, RandomRaysOnABumpyPlaneMatchBruteForce) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(40, 30, 0.15, 2.0, 2.0, 1.5));
  const Bvh bvh(mesh, mesh.positions());
  EXPECT_EQ(bvh.n_faces(), mesh.n_faces());
  check_random_rays(mesh, mesh.positions(), bvh, Vec3(-0.3, -0.3, -0.2), Vec3(2.3, 1.8, 0.2), Vec3(-1, -1, 0.5),
                    Vec3(3, 3, 2), 800, 1, 40);
  // Origins below and between the bumps: rays travel nearly along the surface.
  check_random_rays(mesh, mesh.positions(), bvh, Vec3(-0.3, -0.3, -0.2), Vec3(2.3, 1.8, 0.2), Vec3(-0.5, -0.5, -0.1),
                    Vec3(2.5, 2.0, 0.1), 800, 2, 40);
}

TEST(Bvh, RandomRaysOnAnIcosphereFromOutsideAndInside) {
  const Mesh mesh = Mesh::from_soup(make_icosphere(3, 1.0));
  const Bvh bvh(mesh, mesh.positions());
  check_random_rays(mesh, mesh.positions(), bvh, Vec3::Constant(-1.3), Vec3::Constant(1.3), Vec3::Constant(-4),
                    Vec3::Constant(4), 1500, 3, 100);
  check_random_rays(mesh, mesh.positions(), bvh, Vec3::Constant(-2), Vec3::Constant(2), Vec3::Constant(-0.5),
                    Vec3::Constant(0.5), 500, 4, 0);  // from inside every ray hits
}

TEST(Bvh, RefitAfterMovingVerticesEqualsRebuild) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(30, 30, 0.1, 1.5));
  Bvh refitted(mesh, mesh.positions());
  // A twist plus noise: boxes change a lot, the tree shape is kept.
  VertexData<Vec3> x = mesh.positions();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  for (Vertex v : mesh.vertices()) {
    const Vec3 p = x[v];
    const double a = 1.2 * p.x();
    x[v] = Vec3(p.x(), std::cos(a) * (p.y() - 0.5) - std::sin(a) * p.z(), std::sin(a) * (p.y() - 0.5) + std::cos(a) * p.z()) +
           Vec3(noise(rng), noise(rng), noise(rng));
  }
  refitted.refit(x);
  const Bvh rebuilt(mesh, x);
  EXPECT_EQ(refitted.bounds_min(), rebuilt.bounds_min());
  EXPECT_EQ(refitted.bounds_max(), rebuilt.bounds_max());
  std::mt19937 ray_rng(6);
  for (int r = 0; r < 1000; ++r) {
    const Vec3 o = random_in(ray_rng, Vec3(-1, -2, -2), Vec3(2, 2, 2));
    const Vec3 target = random_in(ray_rng, Vec3(-0.2, -0.7, -0.7), Vec3(1.2, 0.7, 0.7));
    const Ray ray{o, (target - o).normalized()};
    const auto a = refitted.intersect(ray), b = rebuilt.intersect(ray);
    ASSERT_EQ(a.has_value(), b.has_value()) << "ray " << r;
    const Truth truth = brute_force(mesh, x, ray);
    ASSERT_EQ(a.has_value(), truth.face >= 0);
    if (!a) continue;
    EXPECT_EQ(a->face, b->face);
    EXPECT_EQ(a->face.idx(), truth.face);
    EXPECT_NEAR(a->t, b->t, 1e-12 * b->t);
  }
  EXPECT_THROW(refitted.refit(VertexData<Vec3>(3, Vec3::Zero())), InvalidInput);
}

TEST(Bvh, GridAlignedRaysThroughEdgesAndVerticesHit) {
  // Integer grid in z = 0: boxes are flat and rays run exactly along box faces (0 * inf slabs).
  const Mesh mesh = Mesh::from_soup(make_plane(8, 8, 8.0, 8.0));
  const Bvh bvh(mesh, mesh.positions());
  for (int i = 0; i <= 16; ++i)
    for (int j = 0; j <= 16; ++j) {
      const Vec3 o(0.5 * i, 0.5 * j, 2.0);
      const auto down = bvh.intersect(Ray{o, Vec3(0, 0, -1)});
      ASSERT_TRUE(down.has_value()) << o.transpose();
      EXPECT_DOUBLE_EQ(down->t, 2.0);
      const auto slanted = bvh.intersect(Ray{o, Vec3(0, 1, -1).normalized()});
      EXPECT_EQ(slanted.has_value(), j <= 12) << o.transpose();  // lands at y = 0.5 j + 2
    }
  // Parallel to the plane, in it or above it: no hit (grazing rays are not reported).
  EXPECT_FALSE(bvh.intersect(Ray{Vec3(-1, 3.5, 0), Vec3(1, 0, 0)}).has_value());
  EXPECT_FALSE(bvh.intersect(Ray{Vec3(-1, 3.5, 0.1), Vec3(1, 0, 0)}).has_value());
  // Pointing away.
  EXPECT_FALSE(bvh.intersect(Ray{Vec3(4, 4, 1), Vec3(0, 0, 1)}).has_value());
}

TEST(Bvh, RaysThroughEveryVertexOfASphereHitIt) {
  // Vertices are where the most triangles meet: no ray aimed at one may slip through.
  const Mesh mesh = Mesh::from_soup(make_icosphere(3, 1.0));
  const Bvh bvh(mesh, mesh.positions());
  for (Vertex v : mesh.vertices()) {
    const Vec3& p = mesh.position(v);
    const auto from_inside = bvh.intersect(Ray{Vec3::Zero(), p.normalized()});
    ASSERT_TRUE(from_inside.has_value()) << v.idx();
    EXPECT_NEAR(from_inside->t, p.norm(), 1e-12);
    const auto from_outside = bvh.intersect(Ray{3.0 * p, -p.normalized()});
    ASSERT_TRUE(from_outside.has_value()) << v.idx();
    EXPECT_NEAR(from_outside->t, 2.0 * p.norm(), 1e-12);
  }
}

TEST(Bvh, EmptyAndInvalidInput) {
  const Bvh empty;
  EXPECT_FALSE(empty.intersect(Ray{}).has_value());
  EXPECT_FALSE(empty.occluded(Ray{}, 1.0));
  const Mesh mesh = Mesh::from_soup(make_plane(2, 2));
  EXPECT_THROW(Bvh(mesh, VertexData<Vec3>(2, Vec3::Zero())), InvalidInput);
  VertexData<Vec3> x = mesh.positions();
  x[Vertex(4)] = Vec3(NAN, 0, 0);
  EXPECT_THROW(Bvh(mesh, x), InvalidInput);
}

// Build and refit times for ~250k triangles (printed; the assertion only guards against a
// pathological tree).
TEST(Bvh, TimingOn250kTriangles) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(354, 354, 0.05, 4.0));
  using Clock = std::chrono::steady_clock;
  auto ms = [](Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); };
  // Wall time and process CPU time (the latter is less disturbed by other jobs on the machine).
  auto cpu_ms = [] { return 1000.0 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC; };
  double build = INFINITY, build_cpu = INFINITY, refit = INFINITY, refit_cpu = INFINITY;
  Bvh bvh;
  for (int k = 0; k < 3; ++k) {
    const auto t0 = Clock::now();
    const double c0 = cpu_ms();
    bvh = Bvh(mesh, mesh.positions());
    build_cpu = std::min(build_cpu, cpu_ms() - c0);
    build = std::min(build, ms(Clock::now() - t0));
  }
  VertexData<Vec3> x = mesh.positions();
  for (int k = 0; k < 5; ++k) {
    for (Vec3& p : x) p.z() += 0.001;
    const auto t0 = Clock::now();
    const double c0 = cpu_ms();
    bvh.refit(x);
    refit_cpu = std::min(refit_cpu, cpu_ms() - c0);
    refit = std::min(refit, ms(Clock::now() - t0));
  }
  std::mt19937 rng(7);
  const int n_rays = 20000;
  int hits = 0;
  const auto t0 = Clock::now();
  for (int r = 0; r < n_rays; ++r) {
    const Vec3 o = random_in(rng, Vec3(-0.5, -0.5, 1), Vec3(1.5, 1.5, 2));
    const Vec3 target = random_in(rng, Vec3(0, 0, 0), Vec3(1, 1, 0));
    hits += bvh.intersect(Ray{o, (target - o).normalized()}).has_value();
  }
  const double per_ray_us = 1000.0 * ms(Clock::now() - t0) / n_rays;
  std::cout << "[timing] BVH " << mesh.n_faces() << " triangles, " << bvh.n_nodes() << " nodes: build " << build << " ms (cpu "
            << build_cpu << "), refit " << refit << " ms (cpu " << refit_cpu << "), closest hit " << per_ray_us << " us/ray\n";
  EXPECT_GT(hits, n_rays * 9 / 10);
  EXPECT_LT(bvh.n_nodes(), 2 * mesh.n_faces());
}
