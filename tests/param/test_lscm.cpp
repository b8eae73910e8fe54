// LSCM (param/lscm.h): isometric on developable pieces, nearly conformal on curved disks,
// several boundary loops, refusal of what it cannot map, and the flip detector.
#include "freeform/common/error.h"
#include "freeform/mesh/mesh.h"
#include "param/param_fixtures.h"
#include "freeform/param/lscm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace freeform {
namespace {

using test::cone_piece;
using test::cylinder_piece;

// Edge lengths in uv over edge lengths in 3D are one constant (isometry up to similarity).
double edge_ratio_spread(const Mesh& mesh, const std::vector<Vec2>& uv) {
  double lo = 1e300, hi = 0.0;
  for (Edge e : mesh.edges()) {
    const Halfedge h = mesh.halfedge(e, 0);
    const Vertex a = mesh.from_vertex(h), b = mesh.to_vertex(h);
    const double r = (uv[static_cast<std::size_t>(a.idx())] - uv[static_cast<std::size_t>(b.idx())]).norm() /
                     (mesh.position(a) - mesh.position(b)).norm();
    lo = std::min(lo, r);
    hi = std::max(hi, r);
  }
  return hi / lo - 1.0;
}

TEST(Lscm, UnrollsCylinderPieceIsometrically) {
  const Mesh mesh = Mesh::from_soup(cylinder_piece(16, 10));
  const LscmResult r = lscm(mesh);
  EXPECT_EQ(r.distortion.flipped, 0);
  EXPECT_LT(r.distortion.angle_max, 1e-8);
  EXPECT_LT(r.distortion.area_max, 1e-8);
  EXPECT_LT(edge_ratio_spread(mesh, r.uv), 1e-8);
  // The uv area was normalized to the 3D area: the similarity is an isometry.
  for (Edge e : mesh.edges()) {
    const Halfedge h = mesh.halfedge(e, 0);
    const Vertex a = mesh.from_vertex(h), b = mesh.to_vertex(h);
    EXPECT_NEAR((r.uv[static_cast<std::size_t>(a.idx())] - r.uv[static_cast<std::size_t>(b.idx())]).norm(),
                (mesh.position(a) - mesh.position(b)).norm(), 1e-8);
  }
  EXPECT_NE(r.pins[0], r.pins[1]);
  EXPECT_TRUE(mesh.is_boundary(r.pins[0]));
  EXPECT_TRUE(mesh.is_boundary(r.pins[1]));
}

TEST(Lscm, UnrollsConePieceIsometrically) {
  const Mesh mesh = Mesh::from_soup(cone_piece(20, 8));
  const LscmResult r = lscm(mesh);
  EXPECT_EQ(r.distortion.flipped, 0);
  EXPECT_LT(r.distortion.angle_max, 1e-8);
  EXPECT_LT(r.distortion.area_max, 1e-8);
  EXPECT_LT(edge_ratio_spread(mesh, r.uv), 1e-8);
}

TEST(Lscm, CurvedDiskHasSmallAngleDistortionAndNoFlip) {
  const Mesh mesh = Mesh::from_soup(test::spherical_cap(10, 0.9, 1.0));  // a cap of ~64 degrees
  const LscmResult r = lscm(mesh);
  EXPECT_EQ(r.distortion.flipped, 0);
  EXPECT_TRUE(flipped_faces(mesh, r.uv).empty());
  // Measured: mean 0.032, max 0.066 (sigma1 / sigma2 - 1); the discrete cap is not exactly
  // conformally flat, but far from the area distortion (about 0.6 in |ln|).
  EXPECT_LT(r.distortion.angle_mean, 0.05) << "max " << r.distortion.angle_max;
  EXPECT_LT(r.distortion.angle_max, 0.1);
  std::printf("cap: angle distortion mean %.4f max %.4f, area distortion max %.4f\n", r.distortion.angle_mean,
              r.distortion.angle_max, r.distortion.area_max);
  EXPECT_GT(r.distortion.area_max, 0.1);  // a curved cap cannot be mapped isometrically
}

TEST(Lscm, GenusZeroWithSeveralBoundaryLoops) {
  // Annulus lifted onto a paraboloid: two boundary loops, genus 0.
  TriangleSoup soup = make_annulus(0.3, 1.0, 6, 48);
  for (Vec3& p : soup.positions) p.z() = 0.5 * p.head<2>().squaredNorm();
  const Mesh mesh = Mesh::from_soup(soup);
  const PatchTopology t = patch_topology(mesh);
  EXPECT_EQ(t.components, 1);
  EXPECT_EQ(t.boundary_loops, 2);
  EXPECT_EQ(t.genus, 0);
  const LscmResult r = lscm(mesh);
  EXPECT_EQ(r.distortion.flipped, 0);
  EXPECT_LT(r.distortion.angle_mean, 0.05) << "max " << r.distortion.angle_max;
}

TEST(Lscm, TopologyOfGeneratedMeshes) {
  EXPECT_EQ(patch_topology(Mesh::from_soup(test::torus(16, 8))).genus, 1);
  EXPECT_EQ(patch_topology(Mesh::from_soup(test::torus(16, 8))).boundary_loops, 0);
  EXPECT_EQ(patch_topology(Mesh::from_soup(make_icosphere(1))).genus, 0);
  EXPECT_EQ(patch_topology(Mesh::from_soup(make_cylinder(4, 12))).boundary_loops, 2);
}

TEST(Lscm, RefusesWhatHasNoPlanarConformalMap) {
  // Closed sphere: nothing to pin.
  EXPECT_THROW((void)lscm(Mesh::from_soup(make_icosphere(1))), InvalidInput);
  // Torus with one face removed: genus 1, one boundary loop.
  TriangleSoup torus = test::torus(16, 8);
  torus.faces.erase(torus.faces.begin());
  try {
    (void)lscm(Mesh::from_soup(torus));
    FAIL() << "genus 1 accepted";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("genus 1"), std::string::npos) << e.what();
  }
  // Two components.
  TriangleSoup two = make_disk(2);
  const TriangleSoup other = make_disk(2);
  const int off = static_cast<int>(two.positions.size());
  for (const Vec3& p : other.positions) two.positions.push_back(p + Vec3(5, 0, 0));
  for (const Tri& f : other.faces) two.faces.push_back({f[0] + off, f[1] + off, f[2] + off});
  EXPECT_THROW((void)lscm(Mesh::from_soup(two)), InvalidInput);
}

TEST(Lscm, FlipDetectorFindsExactlyTheFoldedTriangles) {
  const Mesh mesh = Mesh::from_soup(make_plane(6, 6));
  std::vector<Vec2> uv;
  for (Vertex v : mesh.vertices()) uv.push_back(mesh.position(v).head<2>());
  EXPECT_TRUE(flipped_faces(mesh, uv).empty());
  EXPECT_EQ(measure_distortion(mesh, uv).flipped, 0);
  EXPECT_LT(measure_distortion(mesh, uv).angle_max, 1e-12);
  // Drag interior vertex (3,3) across its neighbour (4,3): the faces around it that lie on
  // the +x side fold over.
  const int c = 3 * 7 + 3;
  uv[static_cast<std::size_t>(c)] = Vec2(0.75, 0.5);
  std::vector<Face> expected;
  for (Face f : mesh.faces()) {
    const auto v = mesh.vertices(f);
    const Vec2 &a = uv[static_cast<std::size_t>(v[0].idx())], &b = uv[static_cast<std::size_t>(v[1].idx())],
               &d = uv[static_cast<std::size_t>(v[2].idx())];
    if ((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x() <= 0.0) expected.push_back(f);
  }
  ASSERT_FALSE(expected.empty());
  EXPECT_EQ(flipped_faces(mesh, uv), expected);
  EXPECT_EQ(measure_distortion(mesh, uv).flipped, static_cast<int>(expected.size()));
  // Mirroring everything flips every triangle.
  for (Vec2& q : uv) q.x() = -q.x();
  EXPECT_EQ(flipped_faces(mesh, uv).size(), static_cast<std::size_t>(mesh.n_faces()) - expected.size());
  EXPECT_THROW((void)flipped_faces(mesh, std::vector<Vec2>(3)), InvalidInput);
}

}  // namespace
}  // namespace freeform
