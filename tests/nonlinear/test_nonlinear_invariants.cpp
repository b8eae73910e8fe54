// Invariants of the nonlinear model that follow from its definition, independent of any
// reference shape: the rest is a fixed point (exactly), rigid motions of every constraint are
// reproduced, the per-frame drag API converges to the cold solve, and small edits stay close
// to linear BCM with a first-order difference proportional to the rotation (see below).
#include "survey_shapes.h"

#include "freeform/edit/drag_session.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <numbers>

using namespace freeform;
using namespace freeform::test;

namespace {

// A capsule with two handles at its ends (no fixed vertices): every constraint is a handle.
Edit two_ended(const Mesh& mesh, int order, bool fixed_bottom) {
  Edit e;
  e.settings.order = order;
  e.multiresolution = false;
  e.deformation = Deformation::Nonlinear;
  e.nonlinear.tolerance = 1e-9;
  e.nonlinear.max_iterations = 400;
  EditHandle bottom, top;
  for (Vertex v : mesh.vertices()) {
    const double z = mesh.position(v).z();
    if (!fixed_bottom || z >= 0.5) e.support.push_back(v);
    if (z < 0.5) bottom.vertices.push_back(v);
    if (z > 3.5) top.vertices.push_back(v);
  }
  if (!fixed_bottom) e.handles.push_back(bottom);
  e.handles.push_back(top);
  return e;
}

double max_distance(const VertexData<Vec3>& a, const VertexData<Vec3>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a.raw()[i] - b.raw()[i]).norm());
  return d;
}

TEST(Nonlinear, IdentityReturnsTheInputExactly) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  for (int k : {1, 2, 3}) {
    const Edit e = two_ended(mesh, k, true);
    const EditSolver solver(mesh, e);
    VertexData<Vec3> p = mesh.positions();
    solver.evaluate(std::vector<Eigen::Affine3d>(1, Eigen::Affine3d::Identity()), p);
    EXPECT_EQ(max_distance(p, mesh.positions()), 0.0) << "k = " << k;
    EXPECT_TRUE(solver.nonlinear_state()->converged);
  }
}

TEST(Nonlinear, RigidMotionOfEveryConstraintIsRigid) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  Eigen::Affine3d t = Eigen::Translation3d(0.3, -1.0, 2.0) * Eigen::AngleAxisd(2.0, Vec3(1, 2, 3).normalized());
  for (int k : {1, 2, 3}) {
    const Edit e = two_ended(mesh, k, false);
    const EditSolver solver(mesh, e);
    VertexData<Vec3> p = mesh.positions();
    solver.evaluate(std::vector<Eigen::Affine3d>(2, t), p);
    VertexData<Vec3> expected = mesh.positions();
    for (Vec3& x : expected.raw()) x = t * x;
    // 115 degrees: linear BCM shears here. The rigid motion is the fixed point; the iteration
    // stops at its tolerance, 1e-4 of the extent per step: measured 1.1e-8 and 1.2e-8 at k = 2
    // and 3 with the one-sided membrane, below 1e-8 before it.
    EXPECT_LT(max_distance(p, expected), 1e-7) << "k = " << k;
  }
}

TEST(Nonlinear, DragConvergesToTheColdSolve) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  const Edit e = two_ended(mesh, 2, true);
  const EditSolver solver(mesh, e);
  const Vec3 pivot(0, 0, 3.5);
  VertexData<Vec3> drag = mesh.positions(), cold = mesh.positions();
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  {
    DragSession session(solver);
    for (int frame = 1; frame <= 10; ++frame) {  // 9 degrees per frame, each settled (warm starts)
      t = Eigen::Translation3d(pivot) * Eigen::AngleAxisd(frame * 0.05 * std::numbers::pi, Vec3::UnitY()) *
          Eigen::Translation3d(-pivot);
      const DragFrame f = session.finish(std::vector<Eigen::Affine3d>{t}, drag);
      EXPECT_TRUE(f.state.converged) << "frame " << frame;
      EXPECT_GT(f.state.iterations, 0);
    }
  }
  solver.evaluate(std::vector<Eigen::Affine3d>{t}, cold);
  EXPECT_LT(max_distance(drag, cold), 1e-5);
}

// For a handle rotation eps, compare displacements: linear BCM's x(T) - x(I) (it is affine in
// T; x(I) is its smooth fill, not the rest) against the nonlinear x(T) - rest. They differ by
// the rotation of the rest's Laplacian coordinates, a first-order term in eps: the measured
// rate is 2 per halving (not the quadratic rate the issue expected; docs/nonlinear.md).
TEST(Nonlinear, SmallEditsDifferFromLinearBcmAtFirstOrder) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  Edit e = two_ended(mesh, 2, true);
  const EditSolver nonlinear(mesh, e);
  e.deformation = Deformation::Linear;
  const EditSolver linear(mesh, e);
  VertexData<Vec3> fill = mesh.positions();
  linear.evaluate(std::vector<Eigen::Affine3d>(1, Eigen::Affine3d::Identity()), fill);
  std::vector<double> diff, motion;
  for (double eps : {0.04, 0.02, 0.01}) {
    const Eigen::Affine3d t = Eigen::Translation3d(Vec3(0, 0, 3.5)) * Eigen::AngleAxisd(eps, Vec3::UnitX()) *
                              Eigen::Translation3d(Vec3(0, 0, -3.5));
    VertexData<Vec3> a = mesh.positions(), b = mesh.positions();
    nonlinear.evaluate(std::vector<Eigen::Affine3d>{t}, a);
    linear.evaluate(std::vector<Eigen::Affine3d>{t}, b);
    double d = 0, m = 0;
    for (Vertex v : mesh.vertices()) {
      const Vec3 da = a[v] - mesh.position(v), db = b[v] - fill[v];
      d = std::max(d, (da - db).norm());
      m = std::max(m, db.norm());
    }
    diff.push_back(d);
    motion.push_back(m);
    EXPECT_LT(d, 0.25 * m) << "eps " << eps;  // the same edit, up to the rotation of the detail
  }
  EXPECT_NEAR(diff[0] / diff[1], 2.0, 0.2);
  EXPECT_NEAR(diff[1] / diff[2], 2.0, 0.2);
}

TEST(Nonlinear, IterationCapIsReported) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  Edit e = two_ended(mesh, 2, true);
  e.nonlinear.max_iterations = 2;
  const EditSolver solver(mesh, e);
  VertexData<Vec3> p = mesh.positions();
  const Vec3 pivot(0, 0, 3.5);
  solver.evaluate(std::vector<Eigen::Affine3d>{Eigen::Translation3d(pivot) * Eigen::AngleAxisd(2.0, Vec3::UnitY()) *
                                               Eigen::Translation3d(-pivot)},
                  p);
  EXPECT_EQ(solver.nonlinear_state()->iterations, 2);
  EXPECT_FALSE(solver.nonlinear_state()->converged);
  EXPECT_EQ(solver.problems(p).non_finite, 0);
}

// Two capsules side by side (x = 0 and x = 2): two closed components.
TriangleSoup two_capsules(int segments, int rings) {
  TriangleSoup soup = make_capsule(0.5, 4.0, segments, rings);
  const TriangleSoup other = make_capsule(0.5, 4.0, segments, rings);
  const int n = static_cast<int>(soup.positions.size());
  for (const Vec3& p : other.positions) soup.positions.push_back(p + Vec3(2.0, 0.0, 0.0));
  for (Tri t : other.faces) {
    for (int& v : t) v += n;
    soup.faces.push_back(t);
  }
  return soup;
}

// Above 10,000 free vertices the volume term's response is solved together with the step
// (nonlinear_solver.cpp, kJointVolumeMinFree), 3 columns per closed component: the rest is
// still a fixed point, exactly, and a bend keeps the volume of each capsule and converges.
TEST(Nonlinear, LargeSupportsKeepTheRestAndTheVolume) {
  const Mesh mesh = Mesh::from_soup(two_capsules(72, 110));
  const Vec3 pivot(1.0, 0, 3.5);  // about the x axis: both capsules bend the same way
  const std::vector<Eigen::Affine3d> bend{Eigen::Translation3d(pivot) * Eigen::AngleAxisd(1.2, Vec3::UnitX()) *
                                          Eigen::Translation3d(-pivot)};
  const int half = mesh.n_faces() / 2;
  for (int k : {2, 3}) {
    Edit e = two_ended(mesh, k, true);
    e.nonlinear.tolerance = 1e-5;
    const EditSolver solver(mesh, e);
    int free = 0;
    for (Vertex v : mesh.vertices()) free += mesh.position(v).z() >= 0.5 && mesh.position(v).z() <= 3.5;
    ASSERT_GT(free, 10000);
    VertexData<Vec3> p = mesh.positions();
    solver.evaluate(std::vector<Eigen::Affine3d>(1, Eigen::Affine3d::Identity()), p);
    EXPECT_EQ(max_distance(p, mesh.positions()), 0.0) << "k = " << k;
    solver.evaluate(bend, p);
    EXPECT_TRUE(solver.nonlinear_state()->converged) << "k = " << k;
    for (const auto& [first, last] : {std::pair{0, half}, std::pair{half, 2 * half}})
      EXPECT_NEAR(volume(mesh, p, first, last) / volume(mesh, mesh.positions(), first, last), 1.0, 1e-9)
          << "k = " << k << ", faces from " << first;
    EXPECT_GT(min_singular_value(mesh, mesh.positions(), p), 0.6) << "k = " << k;
  }
}

// Two unconnected parts of one support on one closed capsule: the top (z > 4.4) bent 90 degrees
// and the bottom (z < 2.6, about twice as many free vertices) twisted 120 degrees, the band
// between them fixed. Each part takes the settings of its own size and keeps its own volume
// (part_settings.h, enclosed_volume.h), so the joint edit gives each part what editing it alone
// gives: neither the other part's size nor its loss of volume reaches it. Without
// multiresolution: whether the detail is decomposed is decided for the whole support (the
// bottom's detail overhangs its base, the top's alone does not; docs/nonlinear.md, 47).
TEST(Nonlinear, PartsOfOneSupportAreSolvedAsIfAlone) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 6.0, 24, 60));
  const auto in_top = [&](Vertex v) { return mesh.position(v).z() > 4.4; };
  const auto in_bottom = [&](Vertex v) { return mesh.position(v).z() < 2.6; };
  const Eigen::Affine3d bend = Eigen::Translation3d(0, 0, 4.4) *
                               Eigen::AngleAxisd(0.5 * std::numbers::pi, Vec3::UnitX()) *
                               Eigen::Translation3d(0, 0, -4.4);
  const Eigen::Affine3d twist(Eigen::AngleAxisd(2.0 * std::numbers::pi / 3.0, Vec3::UnitZ()));
  const auto edit = [&](bool top, bool bottom, int k) {
    Edit e;
    e.settings.order = k;
    e.deformation = Deformation::Nonlinear;
    e.multiresolution = false;
    e.nonlinear.tolerance = 1e-9;
    EditHandle up, down;
    for (Vertex v : mesh.vertices()) {
      if ((top && in_top(v)) || (bottom && in_bottom(v))) e.support.push_back(v);
      if (top && mesh.position(v).z() > 5.5) up.vertices.push_back(v);
      if (bottom && mesh.position(v).z() < 0.5) down.vertices.push_back(v);
    }
    if (top) e.handles.push_back(up);
    if (bottom) e.handles.push_back(down);
    return e;
  };
  for (int k : {2, 3}) {
    VertexData<Vec3> joint = mesh.positions(), top = joint, bottom = joint;
    const EditSolver both(mesh, edit(true, true, k));
    both.evaluate(std::vector<Eigen::Affine3d>{bend, twist}, joint);
    EditSolver(mesh, edit(true, false, k)).evaluate(std::vector<Eigen::Affine3d>{bend}, top);
    EditSolver(mesh, edit(false, true, k)).evaluate(std::vector<Eigen::Affine3d>{twist}, bottom);
    ASSERT_TRUE(both.nonlinear_state()->converged) << "k = " << k;
    double top_gap = 0.0, bottom_gap = 0.0, moved = 0.0;
    for (Vertex v : mesh.vertices()) {
      const Vec3& alone = in_top(v) ? top[v] : bottom[v];
      (in_top(v) ? top_gap : bottom_gap) = std::max(in_top(v) ? top_gap : bottom_gap, (joint[v] - alone).norm());
      moved = std::max(moved, (joint[v] - mesh.position(v)).norm());
    }
    EXPECT_GT(moved, 1.0) << "k = " << k;
    EXPECT_LT(top_gap, 1e-6) << "k = " << k;
    EXPECT_LT(bottom_gap, 1e-6) << "k = " << k;
  }
}

// A caller (Python's Ctrl-C) can stop a solve between two iterations; the positions stay as
// they were and the next evaluate starts afresh (the same result as without the cancel).
TEST(Nonlinear, EvaluateCanBeCancelledBetweenIterations) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  for (const bool multires : {false, true}) {
    Edit e = two_ended(mesh, 2, true);
    e.multiresolution = multires;
    const EditSolver solver(mesh, e);
    const Vec3 pivot(0, 0, 3.5);
    const std::vector<Eigen::Affine3d> bend{Eigen::Translation3d(pivot) * Eigen::AngleAxisd(1.5, Vec3::UnitY()) *
                                            Eigen::Translation3d(-pivot)};
    std::atomic<bool> cancel{false};
    int steps = 0;
    Progress progress;
    progress.cancel = &cancel;
    progress.report = [&](std::string_view stage, double fraction) {
      EXPECT_EQ(stage, "nonlinear");
      EXPECT_GT(fraction, 0.0);
      if (++steps == 3) cancel = true;
    };
    VertexData<Vec3> p = mesh.positions();
    EXPECT_THROW(solver.evaluate(bend, p, progress), Cancelled);
    EXPECT_EQ(steps, 3);
    EXPECT_EQ(max_distance(p, mesh.positions()), 0.0) << "multires " << multires;
    VertexData<Vec3> full = mesh.positions(), again = mesh.positions();
    solver.evaluate(bend, full);
    solver.evaluate(bend, again);
    EXPECT_EQ(max_distance(full, again), 0.0);
    EXPECT_GT(solver.nonlinear_state()->iterations, 3);
  }
}

}  // namespace
