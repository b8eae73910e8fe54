// Shared fixtures of the BCM tests: small generated meshes, regions, random affine maps and
// an independent reference solve on the GLOBAL operators (operators.h + Eigen SparseLU).
#pragma once

#include "freeform/bcm/bcm_solver.h"
#include "freeform/bcm/bcm_system.h"
#include "freeform/edit/manipulator.h"
#include "freeform/mesh/generators.h"
#include "freeform/operators/operators.h"

#include <Eigen/SparseLU>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace freeform::test {

using RowMatrix = BcmSolver::RowMatrixX3d;

inline std::vector<Vertex> within(const Mesh& mesh, const Vec3& centre, double radius) {
  std::vector<Vertex> out;
  for (Vertex v : mesh.vertices())
    if ((mesh.position(v) - centre).head<2>().norm() < radius) out.push_back(v);
  return out;
}

// Bumpy 24 x 24 plane: support disk of radius 0.38 about the centre with a movable 9-vertex
// handle in the middle, a movable 5-vertex handle and an immovable single-vertex handle.
struct BumpyScene {
  Mesh mesh;
  std::vector<Vertex> support;
  std::vector<HandleRegion> handles;
  BumpyScene() : mesh(Mesh::from_soup(make_bumpy_plane(24, 24, 0.08, 1.5))) {
    support = within(mesh, Vec3(0.5, 0.5, 0), 0.38);
    handles.push_back({within(mesh, Vec3(0.5, 0.5, 0), 0.07), true});
    handles.push_back({within(mesh, Vec3(0.375, 0.625, 0), 0.05), true});
    handles.push_back({within(mesh, Vec3(0.625, 0.375, 0), 0.01), false});
  }
  Regions regions() const { return Regions(mesh, support, handles); }
};

// Planar disk (10 rings, spacing 0.1) with interior vertices jittered in the plane, then moved
// into a general plane by a rigid map. ring[v] is the ring index of vertex v before jitter.
struct PlanarDisk {
  Mesh mesh;
  std::vector<int> ring;
  explicit PlanarDisk(unsigned seed = 7) {
    TriangleSoup soup = make_disk(10, 1.0);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    const Eigen::Matrix3d r = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    for (Vec3& p : soup.positions) {
      const int k = static_cast<int>(std::lround(p.head<2>().norm() / 0.1));
      ring.push_back(k);
      if (k < 10) p += Vec3(u(rng), u(rng), 0.0);
      p = r * p + Vec3(0.3, -0.2, 0.5);
    }
    mesh = Mesh::from_soup(soup);
  }
  std::vector<Vertex> rings(int lo, int hi) const {
    std::vector<Vertex> out;
    for (Vertex v : mesh.vertices())
      if (ring[static_cast<std::size_t>(v.idx())] >= lo && ring[static_cast<std::size_t>(v.idx())] <= hi) out.push_back(v);
    return out;
  }
};

// A random affine map: rotation about a random axis, per-axis scale in [0.6, 1.6], shear-free,
// translation in [-0.3, 0.3]^3, about a random pivot.
inline Eigen::Affine3d random_affine(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Manipulator m;
  m.rotation = Manipulator::axis_angle(Vec3(u(rng), u(rng), u(rng)) + Vec3(0, 0, 1.5), 90.0 * u(rng));
  m.scale = Vec3(1.1 + 0.5 * u(rng), 1.1 + 0.5 * u(rng), 1.1 + 0.5 * u(rng));
  m.translation = 0.3 * Vec3(u(rng), u(rng), u(rng));
  m.pivot = Vec3(0.5 + 0.2 * u(rng), 0.5 + 0.2 * u(rng), 0.1 * u(rng));
  return m.to_affine(Vec3::Zero());
}

// A general affine map with shear (from a 4x4 matrix).
inline Eigen::Affine3d random_general_affine(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Matrix4d mat = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) mat(i, j) += 0.4 * u(rng);
  return affine_from_matrix(mat);
}

inline double lam(double c, int m) { return std::min(1.0, std::max(0.0, c - m + 1.0)); }

// c(v) for every vertex, written out independently of the library.
inline std::vector<double> reference_smoothness(const Regions& regions, const BcmSettings& s) {
  const int k = s.order;
  const double outer = s.smoothness.outer == -1.0 ? k - 1.0 : s.smoothness.outer;
  const double inner = s.smoothness.inner == -1.0 ? k - 1.0 : s.smoothness.inner;
  std::vector<double> c(static_cast<std::size_t>(regions.n_vertices()));
  for (int i = 0; i < regions.n_vertices(); ++i) {
    const Role r = regions.role(Vertex(i));
    c[static_cast<std::size_t>(i)] = r == Role::Free ? k - 1.0 : r == Role::Fixed ? outer : inner;
  }
  for (const SmoothnessSegment& seg : s.smoothness.segments)
    for (Vertex v : seg.vertices)
      if (regions.role(v) != Role::Free) c[static_cast<std::size_t>(v.idx())] = seg.value;
  return c;
}

// Global S_k = L Lam_{k-1} D L ... Lam_1 D L on the whole mesh (#V by #V).
inline Eigen::SparseMatrix<double> global_s(const Mesh& mesh, const Regions& regions, const BcmSettings& s) {
  const Eigen::SparseMatrix<double> lap = cotan_laplacian(mesh);
  const Eigen::VectorXd d = inverse_double_areas(mixed_voronoi_areas(mesh));
  const std::vector<double> c = reference_smoothness(regions, s);
  Eigen::SparseMatrix<double> sk = lap;
  for (int m = 1; m < s.order; ++m) {
    Eigen::VectorXd w(mesh.n_vertices());
    for (int i = 0; i < mesh.n_vertices(); ++i) w[i] = lam(c[static_cast<std::size_t>(i)], m) * d[i];
    sk = Eigen::SparseMatrix<double>(lap * w.asDiagonal() * sk);
  }
  return sk;
}

// Direct solve of S_k[P, P] p = -S_k[P, C] x_C with the handle vertices moved by their
// transforms (immovable handles and fixed vertices at rest). Returns P x 3 in free order.
inline RowMatrix reference_solve(const Mesh& mesh, const Regions& regions, const BcmSettings& s,
                                 const std::vector<Eigen::Affine3d>& transforms) {
  const Eigen::SparseMatrix<double> sk = global_s(mesh, regions, s);
  const int n = mesh.n_vertices();
  std::vector<int> fidx(static_cast<std::size_t>(n), -1);
  const auto& free = regions.free_vertices();
  for (std::size_t i = 0; i < free.size(); ++i) fidx[static_cast<std::size_t>(free[i].idx())] = static_cast<int>(i);
  Eigen::MatrixXd x(n, 3);
  for (Vertex v : mesh.vertices()) {
    Vec3 p = mesh.position(v);
    const int h = regions.handle_of(v);
    if (h >= 0 && regions.movable_index(h) >= 0) p = transforms[static_cast<std::size_t>(regions.movable_index(h))] * p;
    x.row(v.idx()) = p.transpose();
  }
  const auto np = static_cast<int>(free.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(np, 3);
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < sk.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(sk, j); it; ++it) {
      const int i = fidx[static_cast<std::size_t>(it.row())];
      if (i < 0) continue;
      const int fj = fidx[static_cast<std::size_t>(j)];
      if (fj >= 0) t.emplace_back(i, fj, it.value());
      else rhs.row(i) -= it.value() * x.row(j);
    }
  Eigen::SparseMatrix<double> spp(np, np);
  spp.setFromTriplets(t.begin(), t.end());
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(spp);
  EXPECT_EQ(lu.info(), Eigen::Success);
  const Eigen::MatrixXd p = lu.solve(rhs);
  return p;
}

inline RowMatrix evaluate(const BcmSolver& solver, const std::vector<Eigen::Affine3d>& transforms) {
  RowMatrix out(solver.n_free(), 3);
  solver.evaluate(transforms, out);
  return out;
}

// evaluate() with its rows sorted by vertex index, the order of regions.free_vertices() and of
// the references here: the solver's own rows are in breadth-first order (locality).
inline RowMatrix evaluate_by_vertex(const BcmSolver& solver, const std::vector<Eigen::Affine3d>& transforms) {
  const RowMatrix rows = evaluate(solver, transforms);
  const std::vector<Vertex>& free = solver.free_vertices();
  std::vector<int> order(free.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return free[static_cast<std::size_t>(a)] < free[static_cast<std::size_t>(b)];
  });
  RowMatrix out(rows.rows(), 3);
  for (std::size_t r = 0; r < order.size(); ++r) out.row(static_cast<Eigen::Index>(r)) = rows.row(order[r]);
  return out;
}

// max |a - b| / max(max |b|, 1e-300)
inline double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

// A bumpy plane's order-k BCM system: the support x > 0.05, a handle near (0.9, 0.5).
struct PlaneSystem {
  Eigen::SparseMatrix<double> a;
  explicit PlaneSystem(int cells, int order) {
    const Mesh plane = Mesh::from_soup(make_bumpy_plane(cells, cells, 0.05, 2.0));
    std::vector<Vertex> support;
    for (Vertex v : plane.vertices())
      if (plane.position(v).x() > 0.05) support.push_back(v);
    const Regions regions(plane, support, {{within(plane, Vec3(0.9, 0.5, 0), std::max(0.05, 1.2 / cells)), true}});
    BcmSettings settings;
    settings.order = order;
    a = assemble_bcm_system(plane, plane.positions(), regions, settings, false).a_pp;
  }
};

inline Eigen::MatrixXd random_rhs(Eigen::Index rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd b(rows, cols);
  for (Eigen::Index i = 0; i < b.size(); ++i) b.data()[i] = u(rng);
  return b;
}

}  // namespace freeform::test
