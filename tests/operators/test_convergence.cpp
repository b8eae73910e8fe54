// Mean-curvature normal on the sphere: D L x -> -2 H n (H = 1/r, n outward) under refinement,
// and the assembly time on a ~150k-vertex mesh (printed, not asserted).
#include "freeform/mesh/generators.h"
#include "freeform/operators/operators.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

namespace freeform {
namespace {

struct Errors {
  int vertices;
  double max_err;
  double rms_err;
};

// Errors relative to |2H| = 2/r, over all vertices.
Errors sphere_errors(int subdivisions, double r) {
  const Mesh mesh = Mesh::from_soup(make_icosphere(subdivisions, r));
  const SparseMatrix L = cotan_laplacian(mesh);
  const Eigen::VectorXd d = inverse_double_areas(mixed_voronoi_areas(mesh));
  const Eigen::MatrixX3d x = mesh.position_matrix();
  const Eigen::MatrixX3d lap = d.asDiagonal() * (L * x);
  double max_err = 0.0, sum_sq = 0.0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Vec3 p = x.row(i).transpose();
    const Vec3 exact = -2.0 / r * (p / p.norm());  // -2 H n
    const double e = (Vec3(lap.row(i).transpose()) - exact).norm() / (2.0 / r);
    max_err = std::max(max_err, e);
    sum_sq += e * e;
  }
  return {mesh.n_vertices(), max_err, std::sqrt(sum_sq / static_cast<double>(x.rows()))};
}

TEST(Convergence, IcosphereMeanCurvatureNormal) {
  const double r = 2.0;
  std::vector<Errors> errs;
  std::printf("  sub  vertices   max rel err  rate   rms rel err  rate\n");
  for (int s = 0; s <= 6; ++s) {
    errs.push_back(sphere_errors(s, r));
    const Errors& e = errs.back();
    // Rates only where the previous level is not exact to round-off.
    if (errs.size() == 1 || errs[errs.size() - 2].max_err < 1e-12) {
      std::printf("  %3d  %8d   %.3e      -    %.3e      -\n", s, e.vertices, e.max_err, e.rms_err);
    } else {
      const Errors& p = errs[errs.size() - 2];
      std::printf("  %3d  %8d   %.3e   %5.2f   %.3e   %5.2f\n", s, e.vertices, e.max_err,
                  std::log2(p.max_err / e.max_err), e.rms_err, std::log2(p.rms_err / e.rms_err));
    }
  }
  // s = 0, 1 are exact to round-off (see docs/operators.md); convergence from s = 2 on.
  EXPECT_LT(errs[0].max_err, 1e-12);
  EXPECT_LT(errs[1].max_err, 1e-12);
  for (std::size_t i = 3; i < errs.size(); ++i) {
    EXPECT_LT(errs[i].max_err, errs[i - 1].max_err) << "subdivision " << i;
    EXPECT_LT(errs[i].rms_err, errs[i - 1].rms_err) << "subdivision " << i;
  }
  EXPECT_LT(errs.back().max_err, 1e-2);
  EXPECT_LT(errs.back().rms_err, 1e-2);
}

// For a vertex on a sphere with neighbours on it, (x_j - x_i) . n_i = -|x_j - x_i|^2 / (2r), and
// sum_j L_ij |x_j - x_i|^2 = 8 A_i (Voronoi) when no incident triangle is obtuse. So the normal
// component of D L x is exactly -2/r; the whole error above is tangential.
TEST(Convergence, IcosphereNormalComponentIsExact) {
  const double r = 0.7;
  const TriangleSoup soup = make_icosphere(4, r);
  for (const Tri& t : soup.faces) {  // precondition: no obtuse corner
    for (int k = 0; k < 3; ++k) {
      const Vec3& p = soup.positions[static_cast<std::size_t>(t[static_cast<std::size_t>(k)])];
      const Vec3& q = soup.positions[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 1) % 3)])];
      const Vec3& w = soup.positions[static_cast<std::size_t>(t[static_cast<std::size_t>((k + 2) % 3)])];
      ASSERT_GT((q - p).dot(w - p), 0.0);
    }
  }
  const Mesh mesh = Mesh::from_soup(soup);
  const Eigen::MatrixX3d lap =
      inverse_double_areas(mixed_voronoi_areas(mesh)).asDiagonal() * (cotan_laplacian(mesh) * mesh.position_matrix());
  for (Vertex v : mesh.vertices()) {
    const Vec3 n = mesh.position(v).normalized();
    EXPECT_NEAR(Vec3(lap.row(v.idx()).transpose()).dot(n), -2.0 / r, 1e-11);
  }
}

TEST(Timing, AssemblyOn150kVertices) {
  const Mesh mesh = Mesh::from_soup(make_bumpy_plane(386, 386, 0.05, 3.0));  // 149,769 vertices
  double best_l = 1e30, best_a = 1e30;
  Eigen::Index nnz = 0;
#ifdef NDEBUG
  const int reps = 3;
#else
  const int reps = 1;  // debug / sanitizer builds: just exercise the code path
#endif
  for (int rep = 0; rep < reps; ++rep) {
    auto t0 = std::chrono::steady_clock::now();
    const SparseMatrix L = cotan_laplacian(mesh);
    auto t1 = std::chrono::steady_clock::now();
    const Eigen::VectorXd a = mixed_voronoi_areas(mesh);
    auto t2 = std::chrono::steady_clock::now();
    best_l = std::min(best_l, std::chrono::duration<double>(t1 - t0).count());
    best_a = std::min(best_a, std::chrono::duration<double>(t2 - t1).count());
    nnz = L.nonZeros();
    ASSERT_GT(a.minCoeff(), 0.0);
  }
  std::printf("  %d vertices, %d faces: cotan_laplacian %.4f s (nnz %lld), mixed_voronoi_areas %.4f s (best of %d)\n",
              mesh.n_vertices(), mesh.n_faces(), best_l, static_cast<long long>(nnz), best_a, reps);
}

}  // namespace
}  // namespace freeform
