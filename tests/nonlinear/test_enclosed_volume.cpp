// EnclosedVolumes against closed forms: the volume of a sphere and a box-like cylinder, the
// gradient against finite differences, the multiplier against the target it is asked for, the
// volumes of two support parts against the whole mesh's.
#include "freeform/mesh/generators.h"
#include "freeform/nonlinear/enclosed_volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace freeform {
namespace {

using Rows = EnclosedVolumes::RowMatrixX3d;

// Free: the upper half (z > 0); a movable handle: the cap z > 0.8 r; the rest fixed.
struct HalfSphere {
  Mesh mesh;
  Regions regions;
  VertexData<int> local;
  int n_free = 0;
  Rows x;
};

HalfSphere sphere(double radius, const Vec3& centre, int subdivisions = 3) {
  TriangleSoup soup = make_icosphere(subdivisions, radius);
  for (Vec3& p : soup.positions) p += centre;
  Mesh mesh = Mesh::from_soup(soup);
  std::vector<Vertex> support;
  HandleRegion handle;
  for (Vertex v : mesh.vertices()) {
    const double z = mesh.position(v).z() - centre.z();
    if (z > 0.0) support.push_back(v);
    if (z > 0.8 * radius) handle.vertices.push_back(v);
  }
  Regions regions(mesh, support, {handle});
  VertexData<int> local(static_cast<std::size_t>(mesh.n_vertices()), -1);
  int n = 0;
  for (Vertex v : mesh.vertices())
    if (regions.role(v) == Role::Free) local[v] = n++;
  const int n_free = n;
  for (Vertex v : handle.vertices) local[v] = n++;  // the handle rows; the fixed half has none
  Rows x(n, 3);
  for (Vertex v : mesh.vertices())
    if (local[v] >= 0) x.row(local[v]) = mesh.position(v).transpose();
  return {std::move(mesh), std::move(regions), std::move(local), n_free, std::move(x)};
}

TEST(EnclosedVolumes, IcosahedronVolumeAlsoFarFromTheOrigin) {
  // Regular icosahedron of circumradius r: edge a = 4 r / sqrt(10 + 2 sqrt 5), V = 5/12 (3 + sqrt 5) a^3.
  const double r = 2.0, a = 4.0 * r / std::sqrt(10.0 + 2.0 * std::sqrt(5.0));
  const double exact = 5.0 / 12.0 * (3.0 + std::sqrt(5.0)) * a * a * a;
  for (const Vec3& c : {Vec3(0, 0, 0), Vec3(1e6, -2e6, 3e6)}) {
    const HalfSphere s = sphere(r, c, 0);
    const EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
    ASSERT_EQ(v.count(), 1);
    // Far away the input itself is rounded to ~1e-10 of r (3.7e6 / 2^52); the centring keeps
    // the volume from losing more (uncentred, terms of 1e18 would cancel to noise).
    const double volume = v.volume(0, s.x) * std::pow(v.scale(0), 3);
    EXPECT_NEAR(volume / exact, 1.0, c.norm() > 0 ? 1e-9 : 1e-13) << c.transpose();
  }
}

// The faces without a free corner are summed once per start(), at the positions given there:
// with the handle moved (its rows and transform), volume() matches a plain sum over all faces of
// the moved mesh, and a stale sum (the handle cap at its rest) would miss it by the cap's share.
TEST(EnclosedVolumes, VolumeFollowsTheHandleGivenToStart) {
  const HalfSphere s = sphere(1.0, Vec3::Zero());
  EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
  const Eigen::Affine3d t(Eigen::Translation3d(0.1, -0.2, 0.4) * Eigen::AngleAxisd(0.7, Vec3::UnitX()));
  Rows x = s.x;
  for (Eigen::Index i = s.n_free; i < x.rows(); ++i) x.row(i) = (t * Vec3(x.row(i).transpose())).transpose();
  for (Eigen::Index i = 0; i < s.n_free; ++i) x(i, 2) *= 1.3;  // the free rows stretched up
  v.start(std::span(&t, 1), x);
  double expected = 0.0;
  for (Face f : s.mesh.faces()) {
    Vec3 p[3];
    const std::array<Vertex, 3> c = s.mesh.vertices(f);
    for (int k = 0; k < 3; ++k) {
      const int l = s.local[c[static_cast<std::size_t>(k)]];
      p[k] = l >= 0 ? Vec3(x.row(l).transpose()) : s.mesh.position(c[static_cast<std::size_t>(k)]);
    }
    expected += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  EXPECT_NEAR(v.volume(0, x) * std::pow(v.scale(0), 3), expected, 1e-12 * std::abs(expected));
}

// Identity transforms and no scaled handle: the target is the rest volume to the bit, so the
// multiplier is exactly 0 at the rest and the rest stays a fixed point of the model, whatever
// the number of rows (rest * n / n is not the rest for every n).
TEST(EnclosedVolumes, UnscaledTargetIsTheRestVolumeExactly) {
  for (int subdivisions = 1; subdivisions <= 3; ++subdivisions)
    for (int k = 0; k < 12; ++k) {
      const HalfSphere s = sphere(0.5 + 0.37 * k, Vec3(0.1 * k, -0.3, 0.7), subdivisions);
      EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
      const Eigen::Affine3d identity = Eigen::Affine3d::Identity();
      v.start(std::span(&identity, 1), s.x);
      const Eigen::MatrixXd u = s.x.topRows(s.n_free);
      EXPECT_EQ(v.multiplier(0, s.x, u), 0.0) << "subdivisions " << subdivisions << ", sphere " << k;
    }
}

// A sphere with two support parts: the caps above z = 0.3 r and below -0.3 r, each with a
// handle (z beyond 0.85 r), the band between them fixed. Rows: the free vertices, then the
// handles'; part_of_row: 0 up, 1 down.
struct TwoCaps {
  Mesh mesh;
  Regions regions;
  VertexData<int> local;
  int n_free = 0;
  std::vector<int> part_of_row;
  Rows x;
};

TwoCaps two_caps() {
  Mesh mesh = Mesh::from_soup(make_icosphere(3, 1.0));
  std::vector<Vertex> support;
  HandleRegion up, down;
  for (Vertex v : mesh.vertices()) {
    const double z = mesh.position(v).z();
    if (std::abs(z) > 0.3) support.push_back(v);
    if (z > 0.85) up.vertices.push_back(v);
    if (z < -0.85) down.vertices.push_back(v);
  }
  Regions regions(mesh, support, {up, down});
  VertexData<int> local(static_cast<std::size_t>(mesh.n_vertices()), -1);
  std::vector<int> part;
  for (Vertex v : mesh.vertices())
    if (regions.role(v) == Role::Free) {
      local[v] = static_cast<int>(part.size());
      part.push_back(mesh.position(v).z() > 0 ? 0 : 1);
    }
  const int n_free = static_cast<int>(part.size());
  for (const HandleRegion* h : {&up, &down})
    for (Vertex v : h->vertices) {
      local[v] = static_cast<int>(part.size());
      part.push_back(h == &up ? 0 : 1);
    }
  Rows x(static_cast<Eigen::Index>(part.size()), 3);
  for (Vertex v : mesh.vertices())
    if (local[v] >= 0) x.row(local[v]) = mesh.position(v).transpose();
  return {std::move(mesh), std::move(regions), std::move(local), n_free, std::move(part), std::move(x)};
}

// Each support part keeps its own volume, in which the other part stays at rest: the whole
// mesh's change of volume (a plain sum over its faces) is the sum of the parts' changes, each
// part's volume sees only its own rows and handle, and its gradient is 0 on the other's rows.
TEST(EnclosedVolumes, EachSupportPartKeepsItsOwnVolume) {
  const TwoCaps s = two_caps();
  EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions, s.part_of_row);
  ASSERT_EQ(v.count(), 2);
  const double rest0 = v.volume(0, s.x) * std::pow(v.scale(0), 3), rest1 = v.volume(1, s.x) * std::pow(v.scale(1), 3);
  EXPECT_NEAR(rest0, rest1, 1e-14);
  const Eigen::Affine3d t[] = {Eigen::Affine3d(Eigen::AngleAxisd(0.9, Vec3::UnitX())),
                               Eigen::Affine3d(Eigen::Translation3d(0.1, 0.0, -0.3))};
  Rows x = s.x;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const auto part = static_cast<std::size_t>(s.part_of_row[static_cast<std::size_t>(i)]);
    const Vec3 p = x.row(i).transpose();
    x.row(i) = (i < s.n_free ? Vec3(p + 0.1 * p.z() * p) : Vec3(t[part] * p)).transpose();
  }
  v.start(t, x);
  double whole = 0.0;
  for (Face f : s.mesh.faces()) {
    Vec3 p[3];
    const std::array<Vertex, 3> c = s.mesh.vertices(f);
    for (std::size_t k = 0; k < 3; ++k) {
      const int l = s.local[c[k]];
      p[k] = l >= 0 ? Vec3(x.row(l).transpose()) : s.mesh.position(c[k]);
    }
    whole += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  const double now0 = v.volume(0, x) * std::pow(v.scale(0), 3), now1 = v.volume(1, x) * std::pow(v.scale(1), 3);
  EXPECT_GT(std::abs(now0 - rest0), 0.05);
  EXPECT_GT(std::abs(now1 - rest1), 0.05);
  EXPECT_NEAR(whole - rest0, (now0 - rest0) + (now1 - rest1), 1e-12);
  Rows y = x;  // part 1 back at its rest: part 0's volume does not see it
  for (Eigen::Index i = 0; i < y.rows(); ++i)
    if (s.part_of_row[static_cast<std::size_t>(i)] == 1 && i < s.n_free) y.row(i) = s.x.row(i);
  EXPECT_EQ(v.volume(0, y), v.volume(0, x));
  Eigen::MatrixXd g(s.n_free, 3);
  v.gradient(0, x, g);
  for (int i = 0; i < s.n_free; ++i)
    if (s.part_of_row[static_cast<std::size_t>(i)] == 1) {
      EXPECT_EQ(g.row(i).norm(), 0.0) << "row " << i;
    }
  // Without parts, or with parts that share a handle (its motion belongs to both): one volume,
  // the whole mesh's.
  std::vector<int> shared = s.part_of_row;
  shared.back() = 0;  // a row of the lower handle in the upper part
  for (const std::vector<int>& parts : {std::vector<int>(), shared}) {
    EnclosedVolumes one(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions, parts);
    one.start(t, x);
    ASSERT_EQ(one.count(), 1);
    EXPECT_NEAR(one.volume(0, x) * std::pow(one.scale(0), 3), whole, 1e-12);
  }
}

TEST(EnclosedVolumes, GradientMatchesFiniteDifferences) {
  const HalfSphere s = sphere(1.0, Vec3(0.3, 0.1, -0.2));
  const EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
  Rows x = s.x;
  x.topRows(s.n_free).array() += 0.05 * Eigen::ArrayXXd::Random(s.n_free, 3);
  Eigen::MatrixXd g(s.n_free, 3);
  v.gradient(0, x, g);
  for (int i : {0, s.n_free / 2, s.n_free - 1})
    for (int k = 0; k < 3; ++k) {
      const double h = 1e-6;
      Rows a = x, b = x;
      a(i, k) += h;
      b(i, k) -= h;
      // volume() is divided by scale^3, gradient() by scale^2
      EXPECT_NEAR((v.volume(0, a) - v.volume(0, b)) * v.scale(0) / (2 * h), g(i, k), 1e-8);
    }
}

TEST(EnclosedVolumes, MultiplierReachesTheTargetShapesVolume) {
  const HalfSphere s = sphere(1.0, Vec3::Zero());
  EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
  const double rest = v.volume(0, s.x);
  // Shrink the free rows: the multiplier along the outward normals restores the rest volume.
  Rows x = s.x;
  x.topRows(s.n_free) *= 0.9;
  Eigen::MatrixXd u = x.topRows(s.n_free);  // radial
  const double lambda = v.multiplier(0, x, u);
  Rows y = x;
  y.topRows(s.n_free) += lambda * u;
  EXPECT_NEAR(v.volume(0, y) / rest, 1.0, 1e-10);
  EXPECT_EQ(v.multiplier(0, s.x, u), 0.0);  // at rest nothing to do
  // The rows (handle and free half) scaled by 1.5 as the target shape (the fixed half stays):
  // the target is that shape's volume, a plain face sum.
  const Eigen::Affine3d t(Eigen::Scaling(1.5));
  const Rows scaled = 1.5 * s.x;
  v.start(std::span(&t, 1), s.x, &scaled, std::span(&t, 1));
  double expected = 0.0;
  for (Face f : s.mesh.faces()) {
    Vec3 p[3];
    const std::array<Vertex, 3> c = s.mesh.vertices(f);
    for (std::size_t k = 0; k < 3; ++k) {
      const int l = s.local[c[k]];
      p[k] = l >= 0 ? Vec3(scaled.row(l).transpose()) : s.mesh.position(c[k]);
    }
    expected += p[0].dot(p[1].cross(p[2])) / 6.0;
  }
  EXPECT_GT(expected / (rest * std::pow(v.scale(0), 3)), 1.5);
  const double l2 = v.multiplier(0, s.x, u);
  y = s.x;
  y.topRows(s.n_free) += l2 * u;
  EXPECT_NEAR(v.volume(0, y) * std::pow(v.scale(0), 3) / expected, 1.0, 1e-9);
}

// The multiplier is the root of V(x + lambda u) = target nearest to 0, found here by scanning
// lambda: along a direction that changes the volume little or with both signs, Newton from 0
// had returned a far root (a 35k-vertex twist on the bunny moved by 1.7 times its extent) or
// none. No root within the reach (some vertex moved by the component's extent): 0.
// The area of the faces with a free corner at x (other corners at their rest), and the move
// the multiplier allows: kVolumeEfficiency (16) times the even offset |deficit| / area.
double moving_area(const HalfSphere& s, const Rows& x) {
  double area = 0.0;
  for (Face f : s.mesh.faces()) {
    const auto h = s.mesh.halfedges(f);
    const Vertex c[3] = {s.mesh.from_vertex(h[0]), s.mesh.to_vertex(h[0]), s.mesh.to_vertex(h[1])};
    Vec3 p[3];
    bool moves = false;
    for (int k = 0; k < 3; ++k) {
      const int l = s.local[c[k]];
      moves = moves || (l >= 0 && l < s.n_free);
      p[k] = l >= 0 ? Vec3(x.row(l).transpose()) : s.mesh.position(c[k]);
    }
    if (moves) area += 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
  }
  return area;
}

double allowed_move(const HalfSphere& s, const EnclosedVolumes& v, const Rows& x, double target) {
  const double deficit = (v.volume(0, x) - target) * std::pow(v.scale(0), 3);
  return std::min(v.scale(0), 16.0 * std::abs(deficit) / moving_area(s, x));
}

TEST(EnclosedVolumes, MultiplierIsTheRootNearestToZero) {
  const HalfSphere s = sphere(1.0, Vec3(0.2, -0.1, 0.3));
  EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
  Rows x = s.x;
  Eigen::MatrixXd u(s.n_free, 3);
  for (int i = 0; i < s.n_free; ++i) {
    const Vec3 p = s.x.row(i).transpose();
    x.row(i) += 0.05 * Vec3(std::sin(7 * p.y()), std::cos(5 * p.x()), std::sin(3 * p.z())).transpose();
    // Mixed signs (several roots), with enough of a radial part that the roots nearest to 0
    // are within the moves the multiplier allows.
    u.row(i) = (Vec3(std::sin(4 * p.z()) - 0.3, p.y() * p.x(), std::cos(6 * p.x())) +
                2.0 * (p - Vec3(0.2, -0.1, 0.3))).transpose();
  }
  auto volume_at = [&](double lambda) {
    Rows y = x;
    y.topRows(s.n_free) += lambda * u;
    return v.volume(0, y);
  };
  int found = 0;
  for (const double scale : {0.6, 0.9, 0.97, 1.02, 1.1, 1.5, 3.0}) {
    const Eigen::Affine3d t(Eigen::Scaling(scale));
    const Rows scaled = scale * s.x;  // the target shape: the rows and the handle scaled
    v.start(std::span(&t, 1), s.x, &scaled, std::span(&t, 1));
    // The target from a multiplier at the rest shape along the radial field (exact there).
    Eigen::MatrixXd radial = s.x.topRows(s.n_free);
    Rows r = s.x;
    const double radial_lambda = v.multiplier(0, s.x, radial);
    if (radial_lambda == 0.0) continue;  // a target beyond any allowed move: not known here
    r.topRows(s.n_free) += radial_lambda * radial;
    const double target = v.volume(0, r);
    auto f = [&](double lambda) { return volume_at(lambda) - target; };
    const double reach = allowed_move(s, v, x, target) / u.rowwise().norm().maxCoeff();
    // Scan [-reach, reach] for sign changes of V - target; bisect the one nearest to 0.
    const int steps = 4000;
    double nearest = std::numeric_limits<double>::infinity();
    double prev_l = -reach, prev_f = f(prev_l);
    for (int k = 1; k <= steps; ++k) {
      const double l = -reach + 2.0 * reach * k / steps, fl = f(l);
      if ((fl > 0) != (prev_f > 0)) {
        double lo = prev_l, hi = l, flo = prev_f;
        for (int b = 0; b < 60; ++b) {
          const double mid = 0.5 * (lo + hi), fm = f(mid);
          if ((fm > 0) == (flo > 0)) lo = mid, flo = fm; else hi = mid;
        }
        if (std::abs(lo) < std::abs(nearest)) nearest = lo;
      }
      prev_l = l;
      prev_f = fl;
    }
    const double lambda = v.multiplier(0, x, u);
    if (std::isinf(nearest)) {
      EXPECT_EQ(lambda, 0.0) << scale;
    } else {
      ++found;
      EXPECT_NEAR(lambda, nearest, 1e-9 * reach) << scale;
    }
  }
  EXPECT_GE(found, 3);  // the scan found roots for most targets: the test compared something
}

// A direction that mostly slides the surface along itself changes the volume little, so its
// root lies far out: taking it would stretch the soft parts (the armadillo's ears when its
// head turns) instead of inflating the component. The multiplier refuses it; a radial
// direction restores the same deficit.
TEST(EnclosedVolumes, MultiplierRefusesDirectionsThatStretchInsteadOfInflate) {
  const HalfSphere s = sphere(1.0, Vec3(0.2, -0.1, 0.3));
  EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
  Rows x = s.x;
  Eigen::MatrixXd slide(s.n_free, 3), radial(s.n_free, 3);
  for (int i = 0; i < s.n_free; ++i) {
    const Vec3 p = s.x.row(i).transpose() - Vec3(0.2, -0.1, 0.3);
    x.row(i) -= 0.01 * p.transpose();  // 3 % of the free half's volume lost
    slide.row(i) = (Vec3(-p.y(), p.x(), 0.0) + 0.01 * p).transpose();  // a turn about z, a little radial
    radial.row(i) = p.transpose();
  }
  const double target = v.volume(0, s.x);
  auto deficit_along = [&](const Eigen::MatrixXd& u, double lambda) {
    Rows y = x;
    y.topRows(s.n_free) += lambda * u;
    return v.volume(0, y) - target;
  };
  // The sliding direction has a root within the component's extent, beyond 16 even offsets.
  const double allowed = allowed_move(s, v, x, target), extent_reach = v.scale(0) / slide.rowwise().norm().maxCoeff();
  double root = 0.0;
  for (int k = 1; k <= 4000 && root == 0.0; ++k) {
    const double l = extent_reach * k / 4000;
    if ((deficit_along(slide, l) > 0) != (deficit_along(slide, 0) > 0)) root = l;
  }
  ASSERT_GT(root, 0.0);
  ASSERT_GT(root * slide.rowwise().norm().maxCoeff(), allowed);
  EXPECT_EQ(v.multiplier(0, x, slide), 0.0);
  const double lambda = v.multiplier(0, x, radial);
  EXPECT_GT(lambda, 0.0);
  EXPECT_NEAR(deficit_along(radial, lambda), 0.0, 1e-12);
}

// At 1e150 the volume (1e450) and its gradient (1e300 per unit area) would overflow, at
// 1e-150 underflow; scaled by a power of two they are the unit sphere's to rounding.
TEST(EnclosedVolumes, ExtremeSizesNeitherOverflowNorUnderflow) {
  const HalfSphere unit = sphere(1.0, Vec3::Zero());
  const EnclosedVolumes reference(unit.mesh, unit.mesh.positions(), unit.local, unit.n_free, unit.regions);
  Eigen::MatrixXd g_ref(unit.n_free, 3);
  reference.gradient(0, unit.x, g_ref);
  for (const double size : {1e150, 1e-150}) {
    const HalfSphere s = sphere(size, Vec3::Zero());
    const EnclosedVolumes v(s.mesh, s.mesh.positions(), s.local, s.n_free, s.regions);
    Eigen::MatrixXd g(s.n_free, 3);
    v.gradient(0, s.x, g);
    ASSERT_TRUE(g.allFinite()) << size;
    const double ratio = v.scale(0) / reference.scale(0) / size;  // the power of two nearest `size`, relative
    EXPECT_NEAR(v.volume(0, s.x) * std::pow(ratio, 3), reference.volume(0, unit.x), 1e-12) << size;
    EXPECT_LT((g * ratio * ratio - g_ref).cwiseAbs().maxCoeff(), 1e-12) << size;
    Eigen::MatrixXd u = s.x.topRows(s.n_free);
    EnclosedVolumes::RowMatrixX3d shrunk = s.x;
    shrunk.topRows(s.n_free) *= 0.9;
    const double lambda = v.multiplier(0, shrunk, u);
    shrunk.topRows(s.n_free) += lambda * u;
    EXPECT_NEAR(v.volume(0, shrunk) / v.volume(0, s.x), 1.0, 1e-10) << size;
  }
}

TEST(EnclosedVolumes, OpenMeshesHaveNone) {
  const Mesh plane = Mesh::from_soup(make_plane(6, 6));
  std::vector<Vertex> support;
  for (Vertex v : plane.vertices())
    if (plane.position(v).x() > 0.3) support.push_back(v);
  const Regions regions(plane, support, {});
  VertexData<int> local(static_cast<std::size_t>(plane.n_vertices()), -1);
  int n = 0;
  for (Vertex v : support) local[v] = n++;
  EXPECT_EQ(EnclosedVolumes(plane, plane.positions(), local, n, regions).count(), 0);
}

}  // namespace
}  // namespace freeform
