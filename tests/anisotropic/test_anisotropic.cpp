// Anisotropic bending (docs/anisotropic.md, param/anisotropic.h, BcmSettings::anisotropic,
// deform() with the anisotropic setting):
// a long thin support is bent across its whole boundary, the solution is radially symmetric
// in the equalized parameter domain, a round support is unaffected, and the fallbacks are
// taken exactly for genus > 0 (never silently).
#include "bcm/bcm_fixtures.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/common/error.h"
#include "freeform/mesh/traversal.h"
#include "freeform/param/anisotropic.h"
#include "param/param_fixtures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

namespace freeform {
namespace {

using test::RowMatrix;

// Elliptic support x^2/a^2 + y^2/b^2 < 1 (a = aspect, b = 1) on a planar grid of spacing h,
// with a small central disk handle (radius 0.2) lifted by 1 along z.
struct LongSupport {
  double a, b = 1.0, h = 0.1;
  Mesh mesh;
  std::vector<Vertex> support;
  std::vector<HandleRegion> handles;
  explicit LongSupport(double aspect) : a(aspect) {
    const int nx = static_cast<int>(std::lround(2 * (a + 0.4) / h)), ny = static_cast<int>(std::lround(2 * (b + 0.4) / h));
    TriangleSoup soup = make_plane(nx, ny, nx * h, ny * h);
    for (Vec3& p : soup.positions) p -= Vec3(nx * h / 2, ny * h / 2, 0);
    mesh = Mesh::from_soup(soup);
    HandleRegion handle;
    for (Vertex v : mesh.vertices()) {
      const Vec3& p = mesh.position(v);
      if ((p.x() / a) * (p.x() / a) + (p.y() / b) * (p.y() / b) < 1.0 - 1e-9) support.push_back(v);
      if (p.head<2>().norm() < 0.2 + 1e-9) handle.vertices.push_back(v);
    }
    handles.push_back(handle);
  }
  Regions regions() const { return Regions(mesh, support, handles); }
};

// Lifts (z) of the free vertices for the handle moved up by 1.
struct Solution {
  BcmStats stats;
  std::vector<Vertex> free;
  RowMatrix p;
};
Solution solve(const LongSupport& s, int k, bool anisotropic) {
  BcmSettings settings;
  settings.order = k;
  settings.anisotropic = anisotropic;
  const Regions regions = s.regions();
  const BcmSolver solver(s.mesh, regions, settings);
  const std::vector<Eigen::Affine3d> t = {Eigen::Affine3d(Eigen::Translation3d(0, 0, 1))};
  return {solver.stats(), solver.free_vertices(), test::evaluate(solver, t)};
}

// Mean |lift| of the first free ring next to the outer boundary (free vertices with a fixed
// neighbour), near the middle of the long sides (|x| < 0.5) and near the far short ends
// (|x| > a - 0.6, |y| < 0.35).
std::array<double, 2> boundary_ring_lifts(const LongSupport& s, const Solution& sol) {
  const Regions regions = s.regions();
  double sums[2] = {0, 0};
  int counts[2] = {0, 0};
  for (std::size_t i = 0; i < sol.free.size(); ++i) {
    const Vertex v = sol.free[i];
    bool next_to_fixed = false;
    for (Halfedge he : s.mesh.outgoing(v)) next_to_fixed |= regions.role(s.mesh.to_vertex(he)) == Role::Fixed;
    if (!next_to_fixed) continue;
    const Vec3& p = s.mesh.position(v);
    const int side = std::abs(p.x()) < 0.5 ? 0 : (std::abs(p.x()) > s.a - 0.6 && std::abs(p.y()) < 0.35) ? 1 : -1;
    if (side < 0) continue;
    sums[side] += std::abs(sol.p(static_cast<Eigen::Index>(i), 2));
    ++counts[side];
  }
  EXPECT_GT(counts[0], 4);
  EXPECT_GT(counts[1], 4);
  return {sums[0] / counts[0], sums[1] / counts[1]};
}

TEST(Anisotropic, LongSupportCarriesTheDeformationToTheFarEnds) {
  for (double aspect : {4.0, 6.0})
  for (int k : {2, 3}) {
    const LongSupport s(aspect);
    const Solution iso = solve(s, k, false), aniso = solve(s, k, true);
    EXPECT_FALSE(iso.stats.anisotropic);
    EXPECT_TRUE(iso.stats.anisotropic_fallback.empty());
    ASSERT_TRUE(aniso.stats.anisotropic) << aniso.stats.anisotropic_fallback;
    EXPECT_TRUE(aniso.stats.anisotropic_fallback.empty());
    // Extents of the grown support: about 2(a + k h) by 2(b + k h).
    EXPECT_NEAR(aniso.stats.principal_extents[0], 2 * (s.a + k * s.h), 0.25);
    EXPECT_NEAR(aniso.stats.principal_extents[1], 2 * (s.b + k * s.h), 0.25);
    const auto li = boundary_ring_lifts(s, iso), la = boundary_ring_lifts(s, aniso);
    const double ratio_iso = li[0] / li[1], ratio_aniso = la[0] / la[1];
    std::printf("aspect %g, k = %d: first free ring lift, long side / short end: isotropic %.4g / %.4g = %.4g, "
                "anisotropic %.4g / %.4g = %.4g (extents %.3f x %.3f, parametrization %.2f ms)\n",
                s.a, k, li[0], li[1], ratio_iso, la[0], la[1], ratio_aniso, aniso.stats.principal_extents[0],
                aniso.stats.principal_extents[1], aniso.stats.parametrization_ms);
    // Anisotropic: the first ring lift scales like (its distance to the boundary in the
    // equalized domain)^k, and that distance differs by the extent ratio between the long
    // sides and the short ends, so the ratio is about (extent ratio)^k, the whole boundary
    // moves. Isotropic: exponential decay along the support.
    const double extent_ratio = aniso.stats.principal_extents[0] / aniso.stats.principal_extents[1];
    EXPECT_LT(ratio_aniso, std::pow(extent_ratio, k) * 1.3);
    EXPECT_GT(ratio_aniso, std::pow(extent_ratio, k) / 2.0);
    EXPECT_GT(ratio_iso, 1e3);
    EXPECT_GT(ratio_iso, 100 * ratio_aniso);
    // Both reach the handle height at the handle and stay in [0, 1] near it.
    EXPECT_GT(aniso.p.col(2).maxCoeff(), 0.5);
  }
}

// In the equalized parameter domain the elliptic support is a disk: the anisotropic lift is a
// function of the parameter radius alone, up to discretization (and the handle, whose image is
// a small ellipse). The isotropic lift is far from it.
TEST(Anisotropic, SolutionIsRadiallySymmetricInTheParameterDomain) {
  const LongSupport s(4.0);
  const int k = 2;
  std::vector<Vertex> support = s.support;
  const AnisotropicDomain dom = anisotropic_domain(s.mesh, support, k);
  ASSERT_TRUE(dom.used) << dom.fallback;
  EXPECT_EQ(dom.genus, 0);
  EXPECT_EQ(dom.components, 1);
  EXPECT_EQ(dom.flipped, 0);
  EXPECT_LT(dom.angle_distortion_max, 1e-8);  // a planar patch maps by a similarity
  // Radius of the support boundary in the domain: the mean over the first fixed ring.
  const Regions regions = s.regions();
  double r_out = 0.0;
  int n_out = 0;
  for (Vertex v : s.mesh.vertices()) {
    if (regions.role(v) != Role::Fixed) continue;
    for (Halfedge he : s.mesh.outgoing(v))
      if (regions.role(s.mesh.to_vertex(he)) != Role::Fixed) {
        r_out += dom.positions[v].head<2>().norm();
        ++n_out;
        break;
      }
  }
  r_out /= n_out;
  // Residual of a least-squares polynomial (degree 8) in the parameter radius, over the free
  // vertices with 0.35 R <= r <= 0.95 R (the handle image is an ellipse, so not too close).
  const auto spread = [&](const Solution& sol) {
    std::vector<double> rs, zs;
    for (std::size_t i = 0; i < sol.free.size(); ++i) {
      const double r = dom.positions[sol.free[i]].head<2>().norm() / r_out;
      if (r < 0.35 || r > 0.95) continue;
      rs.push_back(r);
      zs.push_back(sol.p(static_cast<Eigen::Index>(i), 2));
    }
    constexpr int kDegree = 8;
    Eigen::MatrixXd vander(static_cast<Eigen::Index>(rs.size()), kDegree + 1);
    for (std::size_t i = 0; i < rs.size(); ++i)
      for (int j = 0; j <= kDegree; ++j) vander(static_cast<Eigen::Index>(i), j) = std::pow(rs[i], j);
    const Eigen::VectorXd z = Eigen::Map<const Eigen::VectorXd>(zs.data(), static_cast<Eigen::Index>(zs.size()));
    const Eigen::VectorXd coef = vander.colPivHouseholderQr().solve(z);
    return (vander * coef - z).cwiseAbs().maxCoeff();  // the handle lift is 1
  };
  const double sa = spread(solve(s, k, true)), si = spread(solve(s, k, false));
  std::printf("max deviation of the lift from a radial profile in the parameter domain (handle lift 1): "
              "anisotropic %.4f, isotropic %.4f\n", sa, si);
  EXPECT_LT(sa, 0.05);  // measured 0.041 (h = 0.1, the handle's image is an ellipse)
  EXPECT_GT(si, 5 * sa);  // measured 0.415
}

// Jittered planar disk in a general plane: the conformal map is a similarity and the principal
// extents are nearly equal, so the anisotropic operator is (nearly) the isotropic one.
TEST(Anisotropic, RoundSupportOnAPlaneIsNearlyIsotropic) {
  const test::PlanarDisk disk;
  const Regions regions(disk.mesh, disk.rings(0, 7), {HandleRegion{disk.rings(0, 1), true}});
  const Eigen::Affine3d t = Eigen::Translation3d(0.1, 0.2, 0.5) * Eigen::AngleAxisd(0.3, Vec3::UnitX());
  for (int k : {1, 2, 3}) {
    BcmSettings settings;
    settings.order = k;
    const BcmSolver iso(disk.mesh, regions, settings);
    settings.anisotropic = true;
    const BcmSolver aniso(disk.mesh, regions, settings);
    ASSERT_TRUE(aniso.stats().anisotropic) << aniso.stats().anisotropic_fallback;
    const auto& e = aniso.stats().principal_extents;
    EXPECT_LT(e[0] / e[1] - 1.0, 0.05);
    const RowMatrix pi = test::evaluate(iso, {t}), pa = test::evaluate(aniso, {t});
    const double d = (pa - pi).cwiseAbs().maxCoeff();
    std::printf("round support, k = %d: extents %.4f x %.4f, max |aniso - iso| = %.3g (handle moved by ~0.55)\n", k, e[0],
                e[1], d);
    EXPECT_LT(d, 0.01);
  }
}

TEST(Anisotropic, KeepsTheBasisInvariants) {
  const test::BumpyScene scene;
  const Regions regions = scene.regions();
  std::vector<Vertex> support;
  for (Vertex v : scene.mesh.vertices())
    if (regions.role(v) != Role::Fixed) support.push_back(v);
  std::mt19937 rng(3);
  for (int k : {2, 3}) {
    BcmSettings s;
    s.order = k;
    s.anisotropic = true;
    const BcmSolver solver(scene.mesh, regions, s);
    ASSERT_TRUE(solver.stats().anisotropic) << solver.stats().anisotropic_fallback;
    EXPECT_GT(solver.stats().parametrization_ms, 0.0);
    // The system on the equalized parameter positions: rows of [A_pp A_pc] sum to zero
    // (constants are reproduced: partition of unity), k = 2 stays symmetric.
    const AnisotropicDomain dom = anisotropic_domain(scene.mesh, support, k);
    ASSERT_TRUE(dom.used);
    const BcmSystem sys = assemble_bcm_system(scene.mesh, dom.positions, regions, s);
    const Eigen::VectorXd rows = sys.a_pp * Eigen::VectorXd::Ones(sys.a_pp.cols()) + sys.a_pc * Eigen::VectorXd::Ones(sys.a_pc.cols());
    double scale = 0.0;
    for (int j = 0; j < sys.a_pp.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(sys.a_pp, j); it; ++it) scale = std::max(scale, std::abs(it.value()));
    EXPECT_LT(rows.cwiseAbs().maxCoeff(), 1e-10 * scale);
    if (k == 2) {
      EXPECT_TRUE(sys.symmetric);
    }
    // Basis result == direct sparse solve of that system with the moved handles.
    const std::vector<Eigen::Affine3d> t = {test::random_affine(rng), test::random_affine(rng)};
    Eigen::MatrixXd xc(static_cast<Eigen::Index>(sys.constrained.size()), 3);
    for (std::size_t j = 0; j < sys.constrained.size(); ++j) {
      const Vertex v = sys.constrained[j];
      const int h = regions.handle_of(v);
      const int m = h >= 0 ? regions.movable_index(h) : -1;
      xc.row(static_cast<Eigen::Index>(j)) = (m >= 0 ? t[static_cast<std::size_t>(m)] * scene.mesh.position(v) : scene.mesh.position(v)).transpose();
    }
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(sys.a_pp);
    ASSERT_EQ(lu.info(), Eigen::Success);
    const Eigen::MatrixXd direct = lu.solve(Eigen::MatrixXd(-(sys.a_pc * xc)));
    EXPECT_LT(test::rel_diff(test::evaluate(solver, t), direct), 1e-8);
  }
}

// Torus helpers: the vertex nearest to the point at tube angles (u, v).
Vertex torus_vertex(const Mesh& mesh, double u, double v) {
  const Vec3 target((1.0 + 0.4 * std::cos(v)) * std::cos(u), (1.0 + 0.4 * std::cos(v)) * std::sin(u), 0.4 * std::sin(v));
  Vertex best;
  double d = 1e300;
  for (Vertex w : mesh.vertices())
    if ((mesh.position(w) - target).norm() < d) {
      d = (mesh.position(w) - target).norm();
      best = w;
    }
  return best;
}

TEST(Anisotropic, FallsBackExactlyForGenusAboveZero) {
  const Mesh mesh = Mesh::from_soup(test::torus(32, 12));
  const Vertex hole = torus_vertex(mesh, 0.0, 0.0), grip = torus_vertex(mesh, std::numbers::pi, 0.0);
  // Support: everything but a small patch (which stays fixed): it contains the torus handle.
  const VertexData<int> dist = ring_distance(mesh, std::vector<Vertex>{hole}, 1);
  std::vector<Vertex> support;
  for (Vertex v : mesh.vertices())
    if (dist[v] < 0) support.push_back(v);
  HandleRegion handle{k_ring(mesh, std::vector<Vertex>{grip}, 1), true};
  std::sort(handle.vertices.begin(), handle.vertices.end());
  const Regions regions(mesh, support, {handle});
  const Eigen::Affine3d t(Eigen::Translation3d(0, 0, 0.2));
  for (int k : {1, 2}) {
    BcmSettings s;
    s.order = k;
    const BcmSolver iso(mesh, regions, s);
    s.anisotropic = true;
    const BcmSolver fallback(mesh, regions, s);
    EXPECT_FALSE(fallback.stats().anisotropic);
    EXPECT_NE(fallback.stats().anisotropic_fallback.find("genus 1"), std::string::npos) << fallback.stats().anisotropic_fallback;
    // The fallback is exactly the isotropic operator.
    EXPECT_LT(test::rel_diff(test::evaluate(fallback, {t}), test::evaluate(iso, {t})), 1e-12);
  }
  // A band around the tube (genus 0, two boundary loops) goes through.
  std::vector<Vertex> band;
  for (Vertex v : mesh.vertices())
    if (std::abs(std::atan2(mesh.position(v).y(), mesh.position(v).x()) - std::numbers::pi / 2) < 0.5) band.push_back(v);
  const Vertex top = torus_vertex(mesh, std::numbers::pi / 2, std::numbers::pi / 2);
  HandleRegion ring{k_ring(mesh, std::vector<Vertex>{top}, 1), true};
  std::sort(ring.vertices.begin(), ring.vertices.end());
  const Regions band_regions(mesh, band, {ring});
  BcmSettings s;
  s.anisotropic = true;
  const BcmSolver solver(mesh, band_regions, s);
  EXPECT_TRUE(solver.stats().anisotropic) << solver.stats().anisotropic_fallback;
  const AnisotropicDomain dom = anisotropic_domain(mesh, band, 2);
  EXPECT_EQ(dom.genus, 0);
  EXPECT_TRUE(dom.used);
}

TEST(Anisotropic, DomainReportsClosedAndEmptyPatches) {
  const Mesh sphere = Mesh::from_soup(make_icosphere(2));
  std::vector<Vertex> all;
  for (Vertex v : sphere.vertices()) all.push_back(v);
  const AnisotropicDomain closed = anisotropic_domain(sphere, all, 2);
  EXPECT_FALSE(closed.used);
  EXPECT_NE(closed.fallback.find("closed"), std::string::npos) << closed.fallback;
  EXPECT_EQ(closed.positions.size(), 0u);
  EXPECT_THROW((void)anisotropic_domain(sphere, std::vector<Vertex>{Vertex(100000)}, 2), InvalidInput);
  EXPECT_THROW((void)anisotropic_domain(sphere, all, 0), InvalidInput);
}

TEST(Anisotropic, DeformWithAnEditFlagUsesIt) {
  const LongSupport s(4.0);
  Edit edit;
  edit.support = s.support;
  EditHandle h;
  h.vertices = s.handles[0].vertices;
  h.manipulator.translation = Vec3(0, 0, 1);
  edit.handles.push_back(h);
  edit.settings.anisotropic = true;
  edit.multiresolution = false;  // a flat plane has no detail; plain BCM
  EditStats stats;
  const Mesh out = deform(s.mesh, edit, &stats);
  EXPECT_TRUE(stats.bcm.anisotropic) << stats.bcm.anisotropic_fallback;
  edit.settings.anisotropic = false;
  (void)deform(s.mesh, edit, &stats);
  EXPECT_FALSE(stats.bcm.anisotropic);
}

}  // namespace
}  // namespace freeform
