// DragSession: frames over an EditSolver whose nonlinear iterations run on a worker thread.
// References: the solver's own cold evaluate() (the fixed point the worker must reach), the
// handles' transforms (handle vertices are exact in every frame), and the prediction's
// definition (the published iterate moved by linear BCM's change).
#include "survey_shapes.h"

#include "freeform/common/error.h"
#include "freeform/edit/drag_session.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

using namespace freeform;
using namespace freeform::test;

namespace {

Edit capsule_edit(const Mesh& mesh, Deformation deformation, bool multires) {
  Edit e;
  e.settings.order = 2;
  e.multiresolution = multires;
  e.deformation = deformation;
  e.nonlinear.tolerance = 1e-9;
  e.nonlinear.max_iterations = 400;
  EditHandle top;
  for (Vertex v : mesh.vertices()) {
    const double z = mesh.position(v).z();
    if (z >= 0.5) e.support.push_back(v);
    if (z > 3.5) top.vertices.push_back(v);
  }
  e.handles.push_back(top);
  return e;
}

std::vector<Eigen::Affine3d> bend(double degrees) {
  const Vec3 pivot(0, 0, 3.5);
  return {Eigen::Translation3d(pivot) * Eigen::AngleAxisd(degrees * std::numbers::pi / 180, Vec3::UnitY()) *
          Eigen::Translation3d(-pivot)};
}

double max_distance(const VertexData<Vec3>& a, const VertexData<Vec3>& b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, (a.raw()[i] - b.raw()[i]).norm());
  return d;
}

void expect_handle_exact(const Mesh& mesh, const Eigen::Affine3d& t, const VertexData<Vec3>& shown) {
  for (Vertex v : mesh.vertices())
    if (mesh.position(v).z() > 3.5) {
      EXPECT_LT((shown[v] - t * mesh.position(v)).norm(), 1e-12) << "handle vertex " << v.idx();
    }
}

}  // namespace

TEST(DragSession, LinearFramesAreTheSolversEvaluate) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  const EditSolver solver(mesh, capsule_edit(mesh, Deformation::Linear, true));
  VertexData<Vec3> expected = mesh.positions(), shown = mesh.positions();
  {
    DragSession drag(solver);
    const DragFrame f = drag.frame(bend(30), shown);
    EXPECT_TRUE(f.written);
    EXPECT_TRUE(f.settled);
    EXPECT_FALSE(f.predicted);
    EXPECT_FALSE(drag.frame(bend(30), shown).written);  // nothing changed
  }
  solver.evaluate(bend(30), expected);
  EXPECT_EQ(max_distance(shown, expected), 0.0);
}

// A drag of 10 frames to 90 degrees without waiting, then finish(): the worker's result is the
// cold solve's fixed point, with and without multiresolution detail.
TEST(DragSession, SettlesOnTheColdSolveAfterAFastDrag) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  for (const bool multires : {false, true}) {
    const EditSolver solver(mesh, capsule_edit(mesh, Deformation::Nonlinear, multires));
    VertexData<Vec3> shown = mesh.positions(), cold = mesh.positions();
    {
      DragSession drag(solver);
      for (int frame = 1; frame <= 10; ++frame) {
        const DragFrame f = drag.frame(bend(9.0 * frame), shown);
        EXPECT_TRUE(f.written);
        // After the first frame (it waits for the worker's start, which may have converged by
        // then) every frame is a prediction for newer transforms: never settled.
        EXPECT_EQ(f.predicted, frame > 1);
        if (frame > 1) {
          EXPECT_FALSE(f.settled);
        }
        expect_handle_exact(mesh, bend(9.0 * frame)[0], shown);
      }
      const DragFrame f = drag.finish(bend(90), shown);
      EXPECT_TRUE(f.settled);
      EXPECT_TRUE(f.state.converged);
      EXPECT_GT(f.state.iterations, 1);
      EXPECT_FALSE(drag.frame(bend(90), shown).written);  // settled: nothing new
      EXPECT_FALSE(drag.error());
    }
    solver.evaluate(bend(90), cold);
    EXPECT_LT(max_distance(shown, cold), 1e-5) << "multires " << multires;
    EXPECT_GT(max_distance(shown, mesh.positions()), 1.0);  // it bent
  }
}

// New transforms while the worker iterates: the frame is written at once from the published
// iterate moved by linear BCM's change (its definition, checked here against the solver's
// linear model), the handle exact. The model never settles here (tolerance 0), so a frame
// that waited for it would hang; the destructor stops the endless worker.
TEST(DragSession, FramesPredictWithoutWaitingForTheWorker) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  Edit e = capsule_edit(mesh, Deformation::Nonlinear, false);
  e.nonlinear.tolerance = 0.0;
  e.nonlinear.max_iterations = std::numeric_limits<int>::max();
  const EditSolver solver(mesh, e);
  VertexData<Vec3> first = mesh.positions(), second = mesh.positions();
  DragSession drag(solver);
  const DragFrame a = drag.frame(bend(40), first);
  ASSERT_TRUE(a.written);
  const DragFrame b = drag.frame(bend(50), second);
  EXPECT_TRUE(b.written);
  EXPECT_TRUE(b.predicted);  // the worker cannot have published 50 degrees before this returned
  EXPECT_FALSE(b.settled);
  expect_handle_exact(mesh, bend(50)[0], second);
  EXPECT_GT(max_distance(first, second), 0.1);
  for (int i = 0; i < 50; ++i) drag.frame(bend(50), second);  // polling while the worker runs
  EXPECT_FALSE(drag.error());
}

// How good the prediction is: after settling at 45 degrees, a frame at 51 is closer to the
// 51-degree solution than the 45-degree frame is (measured 0.070 against 0.109: linear BCM's
// response is only a rough Jacobian of the nonlinear one), and the worker goes on from there
// to the cold solve. Two converged solves are about tolerance / (1 - contraction) apart: with
// the stretch the bent membrane accepts (docs/nonlinear.md, "What the gallery found", 48) the
// last iterations contract slowly, and at a tolerance of 1e-7 they ended 1.1e-5 apart.
TEST(DragSession, PredictionIsCloserThanThePreviousFrame) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  Edit e = capsule_edit(mesh, Deformation::Nonlinear, false);
  e.nonlinear.tolerance = 1e-8;
  const EditSolver solver(mesh, e);
  const auto pulled = [](double degrees) {
    std::vector<Eigen::Affine3d> t = bend(degrees);
    t[0] = t[0] * Eigen::Translation3d(0.2, 0, 0);
    return t;
  };
  VertexData<Vec3> after = mesh.positions(), before = mesh.positions(), shown = mesh.positions();
  solver.evaluate(pulled(51), after);  // the solution of the next frame
  {
    DragSession drag(solver);
    drag.finish(pulled(45), before);
    shown = before;
    const DragFrame p = drag.frame(pulled(51), shown);
    ASSERT_TRUE(p.predicted);
    const double old_error = max_distance(before, after), predicted_error = max_distance(shown, after);
    EXPECT_GT(old_error, 0.05);
    EXPECT_LT(predicted_error, 0.75 * old_error) << old_error;
    expect_handle_exact(mesh, pulled(51)[0], shown);
    EXPECT_TRUE(drag.finish(pulled(51), shown).state.converged);
  }
  EXPECT_LT(max_distance(shown, after), 1e-5);
}

TEST(DragSession, RejectsBadFramesWithoutStoppingTheWorker) {
  const Mesh mesh = Mesh::from_soup(make_capsule(0.5, 4.0, 16, 24));
  const EditSolver solver(mesh, capsule_edit(mesh, Deformation::Nonlinear, false));
  DragSession drag(solver);
  VertexData<Vec3> shown = mesh.positions(), small(3, Vec3::Zero());
  EXPECT_THROW(drag.frame({}, shown), InvalidInput);
  std::vector<Eigen::Affine3d> nan = bend(10);
  nan[0](0, 3) = std::nan("");
  EXPECT_THROW(drag.frame(nan, shown), InvalidInput);
  EXPECT_THROW(drag.frame(bend(10), small), InvalidInput);
  EXPECT_TRUE(drag.finish(bend(10), shown).settled);
  expect_handle_exact(mesh, bend(10)[0], shown);
}
