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

// Every vertex of an open tube along z is a row.
Fans tube_fans() {
  Fans f{Mesh::from_soup(make_cylinder(12, 16, 1.0, 3.0)), {}, {}};
  VertexData<int> local(static_cast<std::size_t>(f.mesh.n_vertices()));
  std::vector<Vertex> global;
  for (Vertex v : f.mesh.vertices()) {
    local[v] = static_cast<int>(global.size());
    global.push_back(v);
    const Vec3 p = f.mesh.position(v);
    f.rest.insert(f.rest.end(), {p.x(), p.y(), p.z()});
  }
  const Eigen::SparseMatrix<double, Eigen::RowMajor> lap = cotan_laplacian(f.mesh);
  f.fans.emplace(f.mesh, local, global, f.rest.data(), lap);
  return f;
}

// A rotation field turning by `rate` radians per unit of height about `axis`.
std::vector<Eigen::Quaterniond> turning(const Fans& f, const Vec3& axis, double rate) {
  std::vector<Eigen::Quaterniond> q;
  for (std::size_t i = 0; i < f.rest.size(); i += 3)
    q.emplace_back(Eigen::AngleAxisd(rate * f.rest[i + 2], axis.normalized()));
  return q;
}

// The field's turn along a tube: twisted about the tube's axis, every face turns more about
// its edges than across them (below 0.5: the axial edges turn about themselves, the diagonals
// partly); bent about an axis across the tube, every face turns more across them (the axial
// edges wholly). Rigid and rest fields do not turn.
TEST(FaceFans, BendFractionTellsABentTubeFromATwistedOne) {
  const Fans f = tube_fans();
  const std::vector<Eigen::Quaterniond> twist = turning(f, Vec3::UnitZ(), 0.6), bend = turning(f, Vec3::UnitY(), 0.6);
  const std::vector<Eigen::Quaterniond> rigid(f.rest.size() / 3,
                                              Eigen::Quaterniond(Eigen::AngleAxisd(2.0, Vec3(1, 2, 3).normalized())));
  const std::vector<Eigen::Quaterniond> rest(f.rest.size() / 3, Eigen::Quaterniond::Identity());
  double bent_sum = 0.0;
  for (int face = 0; face < f.fans->n_faces(); ++face) {
    EXPECT_LT(f.fans->bend_fraction(face, twist, f.rest.data()), 0.5) << face;
    const double b = f.fans->bend_fraction(face, bend, f.rest.data());
    EXPECT_GE(b, 0.5 - 1e-12) << face;
    bent_sum += b;
    EXPECT_EQ(f.fans->bend_fraction(face, rigid, f.rest.data()), 0.0) << face;
    EXPECT_EQ(f.fans->bend_fraction(face, rest, f.rest.data()), 0.0) << face;
  }
  EXPECT_GT(bent_sum / f.fans->n_faces(), 0.7);
}

// where_bent raises the stretch share toward the bent one over the ramp 0.5 .. 0.8 of the bend
// fraction, and never lowers it.
TEST(FaceFans, WhereBentReleasesStretchOnlyWhereTheFieldBends) {
  const OneSided held{1.0, 0.5, 0.0, 1.0};
  EXPECT_EQ(FaceFans::where_bent(held, 0.3).stretch_share, 0.5);
  EXPECT_EQ(FaceFans::where_bent(held, 0.5).stretch_share, 0.5);
  EXPECT_NEAR(FaceFans::where_bent(held, 0.65).stretch_share, 0.75, 1e-12);
  EXPECT_EQ(FaceFans::where_bent(held, 0.8).stretch_share, 1.0);
  EXPECT_EQ(FaceFans::where_bent(held, 1.0).stretch_share, 1.0);
  const OneSided without{1.0, 0.8, 0.0, 0.0};
  EXPECT_EQ(FaceFans::where_bent(without, 1.0).stretch_share, 0.8);
  EXPECT_EQ(FaceFans::where_bent(held, 1.0).compression_gain, 1.0);
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

// The membrane's one-sided target (FaceFans::target_scale): a compressed edge is pushed out
// beyond its rest length, a stretched one pulled back, but not all the way, and never further
// than a bounded scale, however compressed or stretched; continuous at 1, where it is exactly 1.
TEST(FaceFans, OneSidedTargetPushesCompressedEdgesOutAndKeepsPartOfAStretch) {
  EXPECT_EQ(FaceFans::target_scale(1.0), 1.0);
  double last = FaceFans::target_scale(0.2);
  for (double stretch = 0.2; stretch < 1.0; stretch += 0.05) {
    const double s = FaceFans::target_scale(stretch);
    EXPECT_GT(s, 1.0) << stretch;
    EXPECT_LE(s, last) << stretch;  // the more compressed, the further out
    last = s;
  }
  EXPECT_NEAR(FaceFans::target_scale(1.0 - 1e-9), 1.0, 1e-8);
  for (double stretch = 1.05; stretch < 4.0; stretch += 0.05) {
    const double s = FaceFans::target_scale(stretch);
    EXPECT_GT(s, 1.0) << stretch;
    EXPECT_LT(s, stretch) << stretch;
    EXPECT_GE(s, FaceFans::target_scale(stretch - 0.05)) << stretch;
  }
  EXPECT_EQ(FaceFans::target_scale(100.0), FaceFans::target_scale(1000.0));
  EXPECT_EQ(FaceFans::target_scale(-3.0), FaceFans::target_scale(0.0));  // turned against its target
}

// The large supports' target (full resistance to stretch, a smooth onset of the push): exactly 1
// from the rest length on, its slope continuous where the onset ends and at 1 (a kink there
// slowed convergence), and the default's line shifted by half the onset beyond it.
TEST(FaceFans, SmoothOnsetIsContinuouslyDifferentiableAndResistsAllStretch) {
  const OneSided smooth{0.5, 0.0, 0.1};
  for (double stretch = 1.0; stretch < 3.0; stretch += 0.25) EXPECT_EQ(FaceFans::target_scale(stretch, smooth), 1.0);
  const auto slope = [&](double s) {
    const double h = 1e-6;
    return (FaceFans::target_scale(s + h, smooth) - FaceFans::target_scale(s - h, smooth)) / (2.0 * h);
  };
  EXPECT_NEAR(slope(1.0 - 1e-5), 0.0, 1e-4);
  EXPECT_NEAR(slope(0.9 + 1e-5), slope(0.9 - 1e-5), 1e-4);
  EXPECT_NEAR(slope(0.5), -0.5, 1e-9);
  for (double stretch = 0.0; stretch < 0.9; stretch += 0.1)
    EXPECT_NEAR(FaceFans::target_scale(stretch, smooth), FaceFans::target_scale(stretch) - 0.025, 1e-12) << stretch;
  double last = FaceFans::target_scale(0.0, smooth);
  for (double stretch = 0.02; stretch < 1.0; stretch += 0.02) {
    const double s = FaceFans::target_scale(stretch, smooth);
    EXPECT_GT(s, 1.0) << stretch;
    EXPECT_LT(s, last) << stretch;
    last = s;
  }
}

// A grown face's target (OneSided::grown, a target of g times the rest length): an edge whose
// length lies between the rest's and the grown target's is taken as it is (the target scale is
// its own stretch: no force along it), a shorter one is pushed out as an ungrown edge is, from
// its rest length, and a longer one pulled back as before; continuous where the cases meet.
TEST(FaceFans, GrownTargetTakesLengthsBetweenRestAndGrownAndPushesFromTheRest) {
  OneSided grown;
  grown.grown = 1.6;
  for (int i = 0; i <= 6; ++i) {  // lengths in rest lengths
    const double length = 1.0 + 0.1 * i, stretch = length / grown.grown;
    EXPECT_DOUBLE_EQ(FaceFans::target_scale(stretch, grown), stretch) << length;
  }
  for (int i = 2; i <= 9; ++i) {
    const double length = 0.1 * i;
    const double pushed = FaceFans::target_scale(length / grown.grown, grown) * grown.grown;
    EXPECT_NEAR(pushed, FaceFans::target_scale(length), 1e-12) << length;  // in rest lengths
    EXPECT_GT(pushed, 1.0) << length;
  }
  for (double stretch = 1.0; stretch < 2.0; stretch += 0.1)
    EXPECT_EQ(FaceFans::target_scale(stretch, grown), FaceFans::target_scale(stretch)) << stretch;
  const double at_rest = 1.0 / grown.grown;
  EXPECT_NEAR(FaceFans::target_scale(at_rest - 1e-9, grown), at_rest, 1e-8);
  EXPECT_NEAR(FaceFans::target_scale(1.0 - 1e-9, grown), 1.0, 1e-8);
}

// Rigid motions and the rest give the plain right-hand side (every edge's stretch is exactly 1
// at rest), and a uniform shrink by c with identity rotations gives that of the common scale
// target_scale(c): (target_scale(c) - 1) times the rest Laplacian coordinates.
TEST(FaceFans, OneSidedRightHandSideAtRestRigidAndUniformlyShrunk) {
  const Fans f = sphere_fans();
  const int n = f.mesh.n_vertices();
  // The faces' means (FaceFans::mean) of the same rot at every vertex.
  const auto uniform = [&f, n](const Eigen::Matrix3d& m) {
    const std::vector<Eigen::Matrix3d> rot(static_cast<std::size_t>(n), m);
    std::vector<Eigen::Matrix3d> means;
    for (int face = 0; face < f.fans->n_faces(); ++face) means.push_back(f.fans->mean(face, rot));
    return means;
  };
  // Row i of the one-sided right-hand side at x, from the faces' edge terms.
  const auto one_sided = [&f](int i, const std::vector<Eigen::Matrix3d>& means, const std::vector<double>& x) {
    std::vector<FaceFans::EdgeTerms> terms;
    for (int face = 0; face < f.fans->n_faces(); ++face)
      terms.push_back(f.fans->edge_terms(face, means[static_cast<std::size_t>(face)], f.rest.data(), x.data(), {}));
    return f.fans->rotated(i, terms);
  };
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(1.1, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<double> rigid(f.rest.size()), shrunk(f.rest.size());
  const double c = 0.8;
  for (std::size_t i = 0; i < f.rest.size(); i += 3) {
    const Vec3 r(f.rest[i], f.rest[i + 1], f.rest[i + 2]);
    const Vec3 y = rot * r + Vec3(5.0, -3.0, 2.0);
    for (int k = 0; k < 3; ++k) {
      rigid[i + static_cast<std::size_t>(k)] = y(k);
      shrunk[i + static_cast<std::size_t>(k)] = c * r(k);
    }
  }
  const auto zero = uniform(Eigen::Matrix3d::Zero()), turned = uniform(rot - Eigen::Matrix3d::Identity());
  const auto scaled = uniform((FaceFans::target_scale(c) - 1.0) * Eigen::Matrix3d::Identity());
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(one_sided(i, zero, f.rest), Vec3::Zero()) << i;
    const Vec3 plain = f.fans->rotated(i, f.rest.data(), turned);
    EXPECT_LT((one_sided(i, turned, rigid) - plain).norm(), 1e-12 * plain.norm()) << i;
    const Vec3 expected = f.fans->rotated(i, f.rest.data(), scaled);
    EXPECT_LT((one_sided(i, zero, shrunk) - expected).norm(), 1e-12 * expected.norm()) << i;
  }
}

// On a closed mesh whose every vertex is a row, the one-sided right-hand sides sum to zero for
// any positions and rotations (Newton's third law): an edge's term enters the rows at its two
// ends with opposite signs and the same weight (lap is symmetric, and both rows split it between
// the same two faces by the same cotangents). Checked where some edges stretch and others
// compress, with a different rotation at every vertex, against the rows' own size; an edge
// term with the wrong sign at one corner breaks it.
TEST(FaceFans, OneSidedRowsOfAClosedMeshSumToZero) {
  const Fans f = sphere_fans();
  const int n = f.mesh.n_vertices();
  std::vector<Eigen::Matrix3d> rot;
  std::vector<double> x(f.rest.size());
  for (int i = 0; i < n; ++i) {
    rot.push_back(Eigen::AngleAxisd(0.3 * i, Vec3(1.0, std::cos(i), 2.0).normalized()).toRotationMatrix() -
                  Eigen::Matrix3d::Identity());
    for (int k = 0; k < 3; ++k)
      x[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)] =
          f.rest[3 * static_cast<std::size_t>(i) + static_cast<std::size_t>(k)] * (1.0 + 0.3 * std::sin(5.0 * i + k));
  }
  const OneSided one_sided{1.0, 0.2, 0.05};
  std::vector<Eigen::Matrix3d> means;
  std::vector<FaceFans::EdgeTerms> terms;
  for (int face = 0; face < f.fans->n_faces(); ++face) {
    means.push_back(f.fans->mean(face, rot));
    terms.push_back(f.fans->edge_terms(face, means.back(), f.rest.data(), x.data(), one_sided));
  }
  Vec3 sum = Vec3::Zero();
  double size = 0.0;
  for (int i = 0; i < n; ++i) {
    const Vec3 b = f.fans->rotated(i, terms);
    EXPECT_GT((b - f.fans->rotated(i, f.rest.data(), means)).norm(), 1e-6 * b.norm()) << i;  // x matters
    sum += b;
    size += b.norm();
  }
  EXPECT_LT(sum.norm(), 1e-12 * size);
}

}  // namespace
}  // namespace freeform
