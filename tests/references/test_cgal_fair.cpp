// Reference 1 (docs/references.md): BcmSolver at full smoothness (c = k-1) against
// CGAL::Polygon_mesh_processing::fair with fairing_continuity = k-1 on libcgal-demo meshes.
//
// CGAL fair solves Lap^k(x)_i = 0 for the vertices it is given, with
//   Lap(x)_i = 1/(2 A_i) sum_j (cot a_ij + cot b_ij)(x_j - x_i),  A_i = mixed Voronoi area,
// every other vertex fixed and every intermediate Laplacian at full weight. That is the BCM
// system with lambda = 1 everywhere (docs/bcm.md). Differences that remain: CGAL clamps
// cos to [-0.999, 0.999] (|cot| <= 22.3) while we clamp |cot| at 1e5, so patches are chosen
// without such angles and the count is printed.
//
// The only CGAL translation unit of the test suite (CGAL compiles slowly).
#include "freeform/bcm/bcm_solver.h"
#include "freeform/bcm/bcm_system.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"
#include "freeform/mesh/traversal.h"
#include "freeform/regions/regions.h"
#include "test_support.h"

#include <CGAL/Polygon_mesh_processing/fair.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Weights/cotangent_weights.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace {

using namespace freeform;
using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
using SmVertex = SurfaceMesh::Vertex_index;
using RestMap = SurfaceMesh::Property_map<SmVertex, Point>;
// CGAL's own default weights (fair.h), but reading the rest positions instead of the mesh's
// current ones, so that moving the handle first does not change the operator.
using RestWeights = CGAL::Weights::Secure_cotangent_weight_with_voronoi_area<SurfaceMesh, RestMap>;

Point to_point(const Vec3& p) { return {p.x(), p.y(), p.z()}; }
Vec3 to_vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// Surface_mesh whose vertex i is soup vertex i.
SurfaceMesh to_surface_mesh(const TriangleSoup& soup) {
  SurfaceMesh sm;
  for (const Vec3& p : soup.positions) sm.add_vertex(to_point(p));
  for (const Tri& t : soup.faces) {
    const auto f = sm.add_face(SmVertex(static_cast<SurfaceMesh::size_type>(t[0])),
                               SmVertex(static_cast<SurfaceMesh::size_type>(t[1])),
                               SmVertex(static_cast<SurfaceMesh::size_type>(t[2])));
    if (f == SurfaceMesh::null_face()) throw std::runtime_error("CGAL Surface_mesh refused a face");
  }
  return sm;
}

struct Patch {
  Vertex seed;
  std::vector<Vertex> support;  // ring distance <= radius from the seed
  std::vector<Vertex> handle;   // ring distance <= handle_rings
  int radius = 0;
  int clamped_angles = 0;  // angles with |cos| > 0.999 in the faces the system reads
};

// Angles CGAL's clamped cotangent changes (|cos| > 0.999) in faces whose vertices all lie
// within `reach` rings.
int count_clamped_angles(const Mesh& mesh, const VertexData<int>& dist, int reach) {
  int count = 0;
  for (Face f : mesh.faces()) {
    const auto v = mesh.vertices(f);
    bool inside = true;
    for (Vertex x : v) inside = inside && dist[x] >= 0 && dist[x] <= reach;
    if (!inside) continue;
    for (int c = 0; c < 3; ++c) {
      const Vec3 a = mesh.position(v[(c + 1) % 3]) - mesh.position(v[c]);
      const Vec3 b = mesh.position(v[(c + 2) % 3]) - mesh.position(v[c]);
      const double cosine = a.dot(b) / (a.norm() * b.norm());
      if (std::abs(cosine) > 0.999) ++count;
    }
  }
  return count;
}

// A geodesic-ball support of about `target` vertices whose k+1 ring neighbourhood avoids the
// mesh boundary; among a few deterministic seeds, the first one without clamped angles.
Patch choose_patch(const Mesh& mesh, int target, int k, int handle_rings) {
  Patch best;
  best.clamped_angles = std::numeric_limits<int>::max();
  const int n = mesh.n_vertices();
  for (int trial = 1; trial <= 24; ++trial) {
    const Vertex seed(static_cast<int>((static_cast<long long>(n) * trial) / 25));
    const Vertex seeds[] = {seed};
    const VertexData<int> dist = ring_distance(mesh, seeds, 200);
    std::vector<int> per_ring(202, 0);
    for (Vertex v : mesh.vertices())
      if (dist[v] >= 0) ++per_ring[static_cast<std::size_t>(dist[v])];
    int radius = 0, count = per_ring[0];
    while (count < target && radius < 190) count += per_ring[static_cast<std::size_t>(++radius)];
    if (count < target) continue;
    bool near_boundary = false;
    for (Vertex v : mesh.vertices())
      if (dist[v] >= 0 && dist[v] <= radius + k + 1 && mesh.is_boundary(v)) near_boundary = true;
    if (near_boundary) continue;
    const int clamped = count_clamped_angles(mesh, dist, radius + k);
    if (clamped >= best.clamped_angles) continue;
    best = Patch{seed, {}, {}, radius, clamped};
    for (Vertex v : mesh.vertices()) {
      if (dist[v] >= 0 && dist[v] <= radius) best.support.push_back(v);
      if (dist[v] >= 0 && dist[v] <= handle_rings) best.handle.push_back(v);
    }
    if (clamped == 0) break;
  }
  return best;
}

double bbox_diagonal(const Mesh& mesh) {
  Eigen::AlignedBox3d box;
  for (Vertex v : mesh.vertices()) box.extend(mesh.position(v));
  return box.diagonal().norm();
}

// |A_pp x_p + A_pc x_c| / |A_pc x_c| (max over coordinates) of positions x in our system.
double relative_residual(const BcmSystem& sys, const VertexData<Vec3>& x) {
  Eigen::MatrixX3d xp(static_cast<Eigen::Index>(sys.free.size()), 3);
  Eigen::MatrixX3d xc(static_cast<Eigen::Index>(sys.constrained.size()), 3);
  for (std::size_t i = 0; i < sys.free.size(); ++i) xp.row(static_cast<Eigen::Index>(i)) = x[sys.free[i]].transpose();
  for (std::size_t i = 0; i < sys.constrained.size(); ++i)
    xc.row(static_cast<Eigen::Index>(i)) = x[sys.constrained[i]].transpose();
  const Eigen::MatrixX3d rhs = sys.a_pc * xc;
  const Eigen::MatrixX3d res = sys.a_pp * xp + rhs;
  double worst = 0;
  for (int c = 0; c < 3; ++c) worst = std::max(worst, res.col(c).norm() / std::max(rhs.col(c).norm(), 1e-300));
  return worst;
}

struct Case {
  const char* file;
  int target;  // support size
};

// Tolerances on max |ours - CGAL| / bbox diagonal, per order k (docs/references.md): both are
// direct solves of the same system, so the difference is the solvers' rounding amplified by
// the condition number, which grows like (h^-2)^k. Measured maxima (elephant, bunny00,
// armadillo, ~600-2000 free vertices): 7e-15, 4e-12, 5e-8; the bounds leave 20x or more.
constexpr double kTolerance[4] = {0, 1e-12, 1e-9, 1e-6};

void compare_with_cgal(const Case& c, bool move_handle) {
  const std::string path = (freeform::test::cgal_mesh_dir() / c.file).string();
  const TriangleSoup soup = read_mesh(path).soup;
  const Mesh mesh = Mesh::from_soup(soup);
  const double diag = bbox_diagonal(mesh);

  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE(std::string(c.file) + " k=" + std::to_string(k) + (move_handle ? " moved handle" : " no handle"));
    const Patch patch = choose_patch(mesh, c.target, k, 2);
    ASSERT_FALSE(patch.support.empty()) << "no interior patch found";
    EXPECT_EQ(patch.clamped_angles, 0) << "CGAL would clamp cotangents here: the systems differ";

    // Ours.
    std::vector<HandleRegion> handles;
    if (move_handle) handles.push_back(HandleRegion{patch.handle, true});
    const Regions regions(mesh, patch.support, handles);
    BcmSettings settings;
    settings.order = k;
    settings.smoothness.outer = k - 1;
    settings.smoothness.inner = k - 1;
    const BcmSolver solver(mesh, regions, settings);
    std::vector<Eigen::Affine3d> transforms;
    Eigen::Affine3d motion = Eigen::Affine3d::Identity();
    if (move_handle) {
      const Vec3 pivot = solver.handle_centroid(0);
      const Vec3 lift = 0.04 * diag * Vec3(0.3, 0.9, 0.3).normalized();
      motion = Eigen::Translation3d(pivot + lift) * Eigen::AngleAxisd(0.3, Vec3(1, 0.5, -0.2).normalized()) *
               Eigen::Translation3d(-pivot);
      transforms.push_back(motion);
    }
    VertexData<Vec3> ours = mesh.positions();
    solver.evaluate(transforms, ours);

    // CGAL: the handle moved first, then held fixed with everything outside the free set.
    SurfaceMesh sm = to_surface_mesh(soup);
    RestMap rest = sm.add_property_map<SmVertex, Point>("v:freeform_rest").first;
    for (SmVertex v : sm.vertices()) put(rest, v, sm.point(v));
    for (Vertex v : patch.handle)
      if (move_handle) sm.point(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx()))) = to_point(motion * mesh.position(v));
    std::vector<SmVertex> free;
    for (Vertex v : solver.free_vertices()) free.emplace_back(static_cast<SurfaceMesh::size_type>(v.idx()));
    // Without a handle the mesh as passed is the rest shape: use CGAL's defaults untouched.
    const auto continuity = CGAL::parameters::fairing_continuity(static_cast<unsigned>(k - 1));
    const bool ok = move_handle ? CGAL::Polygon_mesh_processing::fair(
                                      sm, free, continuity.weight_calculator(RestWeights(sm, rest)))
                                : CGAL::Polygon_mesh_processing::fair(sm, free, continuity);
    ASSERT_TRUE(ok) << "CGAL fair failed";

    VertexData<Vec3> theirs = mesh.positions();
    for (Vertex v : mesh.vertices()) theirs[v] = to_vec(sm.point(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx()))));
    double diff = 0, moved = 0;
    for (Vertex v : solver.free_vertices()) {
      diff = std::max(diff, (ours[v] - theirs[v]).norm());
      moved = std::max(moved, (theirs[v] - mesh.position(v)).norm());
    }
    const BcmSystem sys = assemble_bcm_system(mesh, mesh.positions(), regions, settings);
    std::printf("[cgal-fair] %-14s %-9s k=%d free=%5d rings=%2d clamped=%d  max|ours-cgal|/diag=%.3e  "
                "max|cgal-rest|/diag=%.3e  residual(ours)=%.1e residual(cgal)=%.1e  solver=%s\n",
                c.file, move_handle ? "handle" : "nohandle", k, solver.n_free(), patch.radius, patch.clamped_angles,
                diff / diag, moved / diag, relative_residual(sys, ours), relative_residual(sys, theirs),
                solver.stats().solver.c_str());
    EXPECT_GT(moved / diag, 1e-4) << "the test would be vacuous: fairing did not move anything";
    EXPECT_LT(diff / diag, kTolerance[k]);
    // Conditioning-free check that both solved the same discrete problem.
    EXPECT_LT(relative_residual(sys, theirs), 1e-10) << "CGAL's solution does not satisfy our system";

    if (move_handle) {
      // The trap: CGAL's default weights read the mesh as passed, i.e. with the handle moved.
      SurfaceMesh distorted = to_surface_mesh(soup);
      for (Vertex v : patch.handle)
        distorted.point(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx()))) = to_point(motion * mesh.position(v));
      ASSERT_TRUE(CGAL::Polygon_mesh_processing::fair(distorted, free, continuity));
      double wrong = 0;
      for (Vertex v : solver.free_vertices())
        wrong = std::max(wrong, (ours[v] - to_vec(distorted.point(SmVertex(static_cast<SurfaceMesh::size_type>(v.idx()))))).norm());
      std::printf("[cgal-fair]   with CGAL's default weights from the moved mesh instead: max|ours-cgal|/diag=%.3e\n",
                  wrong / diag);
    }
  }
}

const Case kCases[] = {{"elephant.off", 600}, {"bunny00.off", 2000}, {"armadillo.off", 2000}};

TEST(CgalFair, FullSmoothnessNoHandleMatchesCgalFair) {
  FREEFORM_REQUIRE_CGAL_MESHES();
  for (const Case& c : kCases) compare_with_cgal(c, false);
}

TEST(CgalFair, MovedHandleAsFixedConstraintMatchesCgalFairWithRestWeights) {
  FREEFORM_REQUIRE_CGAL_MESHES();
  for (const Case& c : kCases) compare_with_cgal(c, true);
}

}  // namespace
