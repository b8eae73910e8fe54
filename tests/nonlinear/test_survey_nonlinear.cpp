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

struct Shape {
  std::string name;
  Mesh mesh;
  Edit edit;
};

struct Result {
  int folds = 0;
  double min_sv = 0, volume_ratio = 0;
  NonlinearState state;
};

// Support: every vertex not fixed; handle: vertices with `is_handle`.
Shape setup(std::string name, const TriangleSoup& soup, const std::function<bool(const Vec3&)>& is_fixed,
            const std::function<bool(const Vec3&)>& is_handle, const Eigen::Affine3d& t) {
  Shape s{std::move(name), Mesh::from_soup(soup), {}};
  EditHandle h;
  for (Vertex v : s.mesh.vertices()) {
    const Vec3& p = s.mesh.position(v);
    if (!is_fixed(p)) s.edit.support.push_back(v);
    if (is_handle(p)) h.vertices.push_back(v);
  }
  h.matrix = t;
  s.edit.handles.push_back(h);
  s.edit.multiresolution = false;
  return s;
}

Eigen::Affine3d rotation_about(const Vec3& pivot, double degrees, const Vec3& axis) {
  return Eigen::Translation3d(pivot) * Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()) *
         Eigen::Translation3d(-pivot);
}

Shape bar_twist() {
  return setup("bar", make_box(1, 1, 5, 10), [](const Vec3& p) { return p.z() < 0.5; },
               [](const Vec3& p) { return p.z() > 4.5; }, rotation_about(Vec3(0.5, 0.5, 0), 135, Vec3::UnitZ()));
}

// The free part (z in [1, 7]) bent into a circular arc of 120 degrees: the handle's base circle
// goes to the arc's end, turned by 120 degrees about y.
Shape cylinder_bend() {
  const double theta = 120.0 * std::numbers::pi / 180.0, rho = 6.0 / theta;
  const Vec3 arc_end(rho - rho * std::cos(theta), 0.0, 1.0 + rho * std::sin(theta));
  const Eigen::Affine3d t =
      Eigen::Translation3d(arc_end) * Eigen::AngleAxisd(theta, Vec3::UnitY()) * Eigen::Translation3d(Vec3(0, 0, -7.0));
  return setup("cylinder", make_capsule(1.0, 8.0, 32, 64), [](const Vec3& p) { return p.z() < 1.0; },
               [](const Vec3& p) { return p.z() > 7.0; }, t);
}

// libcgal-demo's cactus (y up): the right arm, from where it leaves the trunk, bent 70 degrees
// outward about its elbow; the arm's tip is the handle.
std::optional<Shape> cactus_bend() {
  const std::filesystem::path file = cgal_mesh_dir() / "cactus.off";
  if (cgal_mesh_dir().empty() || !std::filesystem::exists(file)) return std::nullopt;
  return setup("cactus", read_mesh(file.string()).soup, [](const Vec3& p) { return p.x() < 0.1; },
               [](const Vec3& p) { return p.x() > 0.2 && p.y() > 0.38; },
               rotation_about(Vec3(0.3, 0.2, 0.0), -70, Vec3::UnitZ()));
}

Result run(Shape s, int order, Deformation model) {
  s.edit.settings.order = order;
  s.edit.deformation = model;
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
// within 15 %. Measured (docs/nonlinear.md): bar k = 2 / 3 volume 0.855 / 0.811 (linear 0.449 /
// 0.584), so k = 3's bound here is 0.8: the bar still necks a little there.
void expect_survey_bounds(const Result& r, double min_volume = 0.85) {
  EXPECT_TRUE(r.state.converged);
  EXPECT_EQ(r.folds, 0);
  EXPECT_GE(r.min_sv, 0.6);
  EXPECT_GE(r.volume_ratio, min_volume);
  EXPECT_LE(r.volume_ratio, 1.15);
}

TEST(SurveyNonlinear, BarTwist135) {
  const Result linear = run(bar_twist(), 2, Deformation::Linear);
  EXPECT_LT(linear.volume_ratio, 0.6);  // what the nonlinear model is for: linear BCM collapses
  expect_survey_bounds(run(bar_twist(), 2, Deformation::Nonlinear));
  expect_survey_bounds(run(bar_twist(), 3, Deformation::Nonlinear), 0.80);
}

TEST(SurveyNonlinear, CylinderBend120) {
  const Result linear = run(cylinder_bend(), 2, Deformation::Linear);
  EXPECT_LT(linear.min_sv, 0.6);
  for (int k : {2, 3}) expect_survey_bounds(run(cylinder_bend(), k, Deformation::Nonlinear));
}

TEST(SurveyNonlinear, CactusArm70) {
  const std::optional<Shape> cactus = cactus_bend();
  if (!cactus) {
    if (data_required()) FAIL() << "cactus.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  run(*cactus, 2, Deformation::Linear);
  for (int k : {2, 3}) expect_survey_bounds(run(*cactus, k, Deformation::Nonlinear));
}

}  // namespace
