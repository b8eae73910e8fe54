// The nonlinear model on the Botsch-Sorkine survey's large-deformation tests, rebuilt from their
// description: a square bar twisted 135 degrees, a capsule bent 120 degrees, libcgal-demo's
// cactus with an arm bent 70 degrees. Judged per edge and per face (folds, collapse) and by the
// enclosed volume, for k = 2 and 3; the linear model is measured on the same set-ups to show
// what the nonlinear one fixes. FREEFORM_SURVEY_OUT=DIR writes the results for rendering.
#include "survey_shapes.h"
#include "test_support.h"

#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/folds.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <optional>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <string>

using namespace freeform;
using namespace freeform::test;

namespace {

struct Result {
  int folds = 0;
  double min_sv = 0, volume_ratio = 0;
  NonlinearState state;
};

Result run(Shape s, int order, Deformation model, bool preserve_volume = true) {
  s.edit.settings.order = order;
  s.edit.deformation = model;
  s.edit.nonlinear.preserve_volume = preserve_volume;
  s.edit.nonlinear.max_iterations = 300;
  const EditSolver solver(s.mesh, s.edit);
  VertexData<Vec3> p = s.mesh.positions();
  solver.evaluate(solver.transforms(s.edit), p);
  Result r;
  r.folds = count_folded_edges(s.mesh, s.mesh.positions(), p);
  r.min_sv = min_singular_value(s.mesh, s.mesh.positions(), p);
  r.volume_ratio = volume(s.mesh, p) / volume(s.mesh, s.mesh.positions());
  if (const NonlinearState* st = solver.nonlinear_state()) r.state = *st;
  std::printf("%-9s k=%d %-9s folds %4d  min sv %.3f  volume %.3f  iterations %d residual %.2g %.0f ms\n",
              s.name.c_str(), order, std::string(deformation_name(model)).c_str(), r.folds, r.min_sv, r.volume_ratio,
              r.state.iterations, r.state.step, r.state.ms);
  if (const char* dir = std::getenv("FREEFORM_SURVEY_OUT")) {
    TriangleSoup soup = s.mesh.to_soup();
    soup.positions = p.raw();
    const std::string stem = std::string(dir) + "/" + s.name + "-k" + std::to_string(order) + "-" +
                             std::string(deformation_name(model));
    write_mesh(stem + ".off", soup);
  }
  return r;
}

// The bounds: no folded edge, no face squeezed below 0.6 in any direction, volume
// within 15 %; with the volume term (the default) the volume is kept (to the Newton tolerance
// of its multiplier, far below the iteration's tolerance).
void expect_survey_bounds(const Result& r) {
  EXPECT_TRUE(r.state.converged);
  EXPECT_EQ(r.folds, 0);
  EXPECT_GE(r.min_sv, 0.6);
  EXPECT_NEAR(r.volume_ratio, 1.0, 1e-6);
}

TEST(SurveyNonlinear, BarTwist135) {
  const Result linear = run(bar_twist(), 2, Deformation::Linear);
  EXPECT_LT(linear.volume_ratio, 0.6);  // what the nonlinear model is for: linear BCM collapses
  for (int k : {2, 3}) expect_survey_bounds(run(bar_twist(), k, Deformation::Nonlinear));
}

// Without the volume term the model keeps lengths like ARAP and the twisted bar necks
// (measured 0.857 / 0.825 for k = 2 / 3; ARAP 0.72): still no fold and no collapse.
TEST(SurveyNonlinear, WithoutTheVolumeTermTheBarNecks) {
  for (int k : {2, 3}) {
    const Result r = run(bar_twist(), k, Deformation::Nonlinear, false);
    EXPECT_TRUE(r.state.converged);
    EXPECT_EQ(r.folds, 0);
    EXPECT_GE(r.min_sv, 0.6);
    EXPECT_LT(r.volume_ratio, 0.87);
    EXPECT_GT(r.volume_ratio, 0.8);
  }
}

TEST(SurveyNonlinear, CylinderBend120) {
  const Result linear = run(cylinder_bend(), 2, Deformation::Linear);
  EXPECT_LT(linear.min_sv, 0.6);
  for (int k : {2, 3}) expect_survey_bounds(run(cylinder_bend(), k, Deformation::Nonlinear));
}

TEST(SurveyNonlinear, CactusArm70) {
  const std::optional<Shape> cactus = cgal_mesh_dir().empty() ? std::nullopt : cactus_bend(cgal_mesh_dir());
  if (!cactus) {
    if (data_required()) FAIL() << "cactus.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  run(*cactus, 2, Deformation::Linear);
  for (int k : {2, 3}) expect_survey_bounds(run(*cactus, k, Deformation::Nonlinear));
}

}  // namespace
