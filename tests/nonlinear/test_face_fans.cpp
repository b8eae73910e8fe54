#include "freeform/nonlinear/face_fans.h"

#include "freeform/mesh/generators.h"
#include "freeform/nonlinear/rotation.h"
#include "freeform/operators/operators.h"

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include <cmath>
#include <optional>
#include <vector>

namespace freeform {
namespace {

struct Fans {
  Mesh mesh;
  std::vector<double> rest;
  std::optional<FaceFans> fans;
};

// Every vertex of an irregular sphere is a row.
Fans sphere_fans() {
  Fans f{Mesh::from_soup(make_icosphere(2, 1.0)), {}, {}};
  VertexData<int> local(static_cast<std::size_t>(f.mesh.n_vertices()));
  std::vector<Vertex> global;
  for (Vertex v : f.mesh.vertices()) {
    // A jitter, so that the cotangents differ from face to face.
    const Vec3 p = f.mesh.position(v) * (1.0 + 0.1 * std::sin(7.0 * v.idx()));
    local[v] = static_cast<int>(global.size());
    global.push_back(v);
    f.rest.insert(f.rest.end(), {p.x(), p.y(), p.z()});
  }
  for (Vertex v : f.mesh.vertices())
    f.mesh.position(v) =
        Vec3(f.rest[3 * static_cast<std::size_t>(v.idx())], f.rest[3 * static_cast<std::size_t>(v.idx()) + 1],
             f.rest[3 * static_cast<std::size_t>(v.idx()) + 2]);
  const Eigen::SparseMatrix<double, Eigen::RowMajor> lap = cotan_laplacian(f.mesh);
  f.fans.emplace(f.mesh, local, global, f.rest.data(), lap);
  return f;
}

// A rigid motion's covariance is R times sum w e e^T: R^T C symmetric and positive
// semidefinite, and the fit returns R. A spoke gathered with a wrong sign or endpoint breaks
// the symmetry.
TEST(FaceFans, CovarianceOfARigidMotionIsTheRotationTimesAnEdgeTensor) {
  const Fans f = sphere_fans();
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(1.1, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Vec3 shift(5.0, -3.0, 2.0);
  std::vector<double> x(f.rest.size());
  for (std::size_t i = 0; i < f.rest.size(); i += 3) {
    const Vec3 y = rot * Vec3(f.rest[i], f.rest[i + 1], f.rest[i + 2]) + shift;
    for (int k = 0; k < 3; ++k) x[i + static_cast<std::size_t>(k)] = y(k);
  }
  for (int i = 0; i < f.mesh.n_vertices(); ++i) {
    const Eigen::Matrix3d c = f.fans->covariance(i, x.data()), s = rot.transpose() * c;
    EXPECT_LT((s - s.transpose()).norm(), 1e-12 * s.norm()) << i;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 * (s + s.transpose()));
    EXPECT_GT(eig.eigenvalues().minCoeff(), -1e-12 * s.norm()) << i;
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    extract_rotation(c, q);
    EXPECT_LT((q.toRotationMatrix() - rot).norm(), 1e-9) << i;
  }
}

}  // namespace
}  // namespace freeform
