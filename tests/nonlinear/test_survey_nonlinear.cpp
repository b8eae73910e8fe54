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
#include "freeform/multires/multires_solver.h"
#include "freeform/nonlinear/nonlinear_solver.h"
#include "freeform/regions/selectors.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <string>

using namespace freeform;
using namespace freeform::test;

namespace {

struct Result {
  int folds = 0;
  double min_sv = 0, volume_ratio = 0;
  NonlinearState state;
};

Result run(Shape s, int order, Deformation model, bool preserve_volume = true, int max_iterations = 300) {
  s.edit.settings.order = order;
  s.edit.deformation = model;
  s.edit.nonlinear.preserve_volume = preserve_volume;
  s.edit.nonlinear.max_iterations = max_iterations;
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

// A prismatic bar twisted by its ends turns its cross-sections at a uniform rate (Saint-Venant
// torsion); the smooth boundary ramps the rate up from 0 at the constrained ends, so its peak is
// about 1.4 times the mean. A membrane that released stretch on this support buckled the bar in
// its middle, the twist gathered there at 4.6 times the mean rate (docs/nonlinear.md, "What the
// gallery found", 40).
TEST(SurveyNonlinear, BarTwistSpreadsAlongTheBar) {
  const Shape s = bar_twist();
  const VertexData<Vec3>& rest = s.mesh.positions();
  // Per height of the rest's grid: the corners (0, 0, z) and (1, 1, z) of the square section.
  std::map<long, std::array<Vertex, 2>> diagonal;
  for (Vertex v : s.mesh.vertices()) {
    const Vec3 r = rest[v];
    const bool low = r.x() == 0.0 && r.y() == 0.0, high = r.x() == 1.0 && r.y() == 1.0;
    if (low || high) diagonal[std::lround(r.z() * 10)][high ? 1 : 0] = v;
  }
  ASSERT_EQ(diagonal.size(), 51u);
  for (int k : {2, 3}) {
    Shape edit = s;
    edit.edit.settings.order = k;
    edit.edit.deformation = Deformation::Nonlinear;
    const EditSolver solver(edit.mesh, edit.edit);
    VertexData<Vec3> p = rest;
    solver.evaluate(solver.transforms(edit.edit), p);
    std::vector<double> angle;
    for (const auto& [z, corners] : diagonal) {
      const Vec3 d = p[corners[1]] - p[corners[0]];
      const double a = std::atan2(d.y(), d.x());
      angle.push_back(angle.empty() ? a : angle.back() + std::remainder(a - angle.back(), 2 * std::numbers::pi));
    }
    const double total = angle.back() - angle.front();
    EXPECT_NEAR(total * 180 / std::numbers::pi, 135.0, 1e-6) << "k = " << k;
    double peak = 0;
    for (std::size_t i = 1; i < angle.size(); ++i) peak = std::max(peak, (angle[i] - angle[i - 1]) * 50 / total);
    EXPECT_LT(peak, 2.0) << "k = " << k << ": the twist gathers at " << peak << " times its mean rate";
  }
}

// Without the volume term the model keeps lengths like ARAP and the twisted bar necks
// (measured 0.704 / 0.694 for k = 2 / 3 since the k = 3 membrane of 2026-12-04, 0.704 / 0.717
// before it, 0.857 / 0.825 before the spokes-and-rims membrane; ARAP 0.72): still no fold and
// no collapse. (A k = 3 membrane of 0.03 (500 / free) instead of (500 / free)^1.5 cycles here:
// 300 iterations, 4 folded edges.)
TEST(SurveyNonlinear, WithoutTheVolumeTermTheBarNecks) {
  for (int k : {2, 3}) {
    const Result r = run(bar_twist(), k, Deformation::Nonlinear, false);
    EXPECT_TRUE(r.state.converged);
    EXPECT_EQ(r.folds, 0);
    EXPECT_GE(r.min_sv, 0.6);
    EXPECT_LT(r.volume_ratio, 0.87);
    EXPECT_GT(r.volume_ratio, 0.68);
  }
}

TEST(SurveyNonlinear, CylinderBend120) {
  const Result linear = run(cylinder_bend(), 2, Deformation::Linear);
  EXPECT_LT(linear.min_sv, 0.6);
  for (int k : {2, 3}) expect_survey_bounds(run(cylinder_bend(), k, Deformation::Nonlinear));
}

// The survey's cylinder with flat caps and multiresolution on (the default): the membrane fill
// of a long tube pinches toward its axis, so a decomposition would make the whole radius
// "detail" (measured before the fix: k = 2 tore, 2,057 folded edges, min sigma 0; k = 3 a
// singular base system). Multiresolution must never be worse than without it.
TEST(SurveyNonlinear, FlatCylinderBendWithMultiresolution) {
  for (int k : {2, 3}) {
    const Result with = run(flat_cylinder_bend(), k, Deformation::Nonlinear);
    Shape off = flat_cylinder_bend();
    off.edit.multiresolution = false;
    const Result without = run(off, k, Deformation::Nonlinear);
    // The bounds: no folded edge, no collapsed face (sigma < 0.5), the volume kept.
    EXPECT_TRUE(with.state.converged);
    EXPECT_EQ(with.folds, 0);
    EXPECT_GE(with.min_sv, 0.5);  // measured 0.60 / 0.56 at k = 2 / 3, the same as without
    EXPECT_NEAR(with.volume_ratio, 1.0, 1e-6);
    EXPECT_LE(with.folds, without.folds);
    EXPECT_GE(with.min_sv, without.min_sv - 0.02);
    // The linear model on the same decomposition-hostile support: a result, no solver error.
    EXPECT_NO_THROW(run(flat_cylinder_bend(), k, Deformation::Linear));
  }
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

// The whole cactus bent sideways about its foot, arms included (gallery_cases.h's
// "cactus-whole"). At k = 3, before the membrane term (NonlinearOptions::membrane), the model's
// own fixed point was bad (6 folded edges, min sigma 0.16, one arm through the trunk): the order-3
// energy is the Dirichlet energy of the Laplacian mismatch M^-1 (L x - b(R)), and an arm that
// bends with a uniform mismatch costs it nothing. Now: 0 folds, min sigma 0.62 (k = 2: 0.66).
void expect_cactus_whole_bend(int k) {
  const std::optional<Shape> cactus = cgal_mesh_dir().empty() ? std::nullopt : cactus_whole_bend(cgal_mesh_dir());
  if (!cactus) {
    if (data_required()) FAIL() << "cactus.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  const Result r = run(*cactus, k, Deformation::Nonlinear, true, NonlinearOptions{}.max_iterations);
  EXPECT_TRUE(r.state.converged);
  EXPECT_EQ(r.folds, 0);
  EXPECT_GE(r.min_sv, 0.5);  // k = 2: 0.67
}

TEST(SurveyNonlinear, CactusWholeBend70) { expect_cactus_whole_bend(2); }
TEST(SurveyNonlinear, CactusWholeBend70AtOrder3) { expect_cactus_whole_bend(3); }

// Detail that overhangs its smooth base (here the bunny's ear, whose two sides the base flattens
// into one sheet) does not ride on the base's normals through a large rotation: decomposed, the
// ear twisted 90 degrees tore (446 folded edges measured). With multiresolution on, the
// nonlinear model therefore carries such detail itself, on the detailed mesh.
TEST(SurveyNonlinear, OverhangingDetailIsCarriedByTheModel) {
  const std::filesystem::path file = cgal_mesh_dir().empty() ? "" : cgal_mesh_dir() / "bunny00.off";
  if (file.empty() || !std::filesystem::exists(file)) {
    if (data_required()) FAIL() << "bunny00.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  Shape s{"bunny-ear", Mesh::from_soup(read_mesh(file.string()).soup), {}};
  const Mesh& mesh = s.mesh;
  Vertex tip(0);
  for (Vertex v : mesh.vertices())
    if (mesh.position(v).y() > mesh.position(tip).y()) tip = v;
  const VertexData<Vec3>& rest = mesh.positions();
  Vec3 lo = rest[Vertex(0)], hi = lo;
  for (const Vec3& p : rest.raw()) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = (hi - lo).norm();
  s.edit.settings.order = 3;
  s.edit.support = select_geodesic(mesh, mesh.position(tip), 0.35 * extent, "support");
  EditHandle h;
  h.vertices = select_geodesic(mesh, mesh.position(tip), 0.08 * extent, "handle");
  Vec3 centroid = Vec3::Zero();
  for (Vertex v : h.vertices) centroid += mesh.position(v) / static_cast<double>(h.vertices.size());
  h.matrix = rotation_about(centroid, 90, Vec3::UnitY());
  s.edit.handles.push_back(h);
  s.edit.deformation = Deformation::Nonlinear;
  ASSERT_TRUE(s.edit.multiresolution);  // the default

  const EditSolver solver(mesh, s.edit);
  ASSERT_TRUE(solver.stats().multires.has_value());
  EXPECT_TRUE(solver.stats().multires->detail_by_model);
  VertexData<Vec3> identity = rest;
  solver.evaluate(std::vector<Eigen::Affine3d>{Eigen::Affine3d::Identity()}, identity);
  EXPECT_EQ(identity.raw(), rest.raw());  // the rest exactly, detail included
  const Result r = run(s, 3, Deformation::Nonlinear);
  EXPECT_TRUE(r.state.converged);
  EXPECT_EQ(r.folds, 0);
  EXPECT_GE(r.min_sv, 0.4);  // measured 0.45 (a thin blade twisted next to the handle); decomposed 0.036

  // What the decomposition did with the same edit: the ear's detail re-added along the turned
  // base normals folds edges and squeezes faces (446 folded edges before the membrane term, 60
  // with it; 3 with a minimum singular value of 0.11 since the membrane's ill-conditioned fits
  // turn with the field, docs/nonlinear.md, "What the gallery found", 51).
  MultiresOptions options;
  options.model = nonlinear_base_model(s.edit.nonlinear);
  const MultiresSolver decomposed(mesh, edit_regions(mesh, s.edit), s.edit.settings, options);
  VertexData<Vec3> p = rest;
  decomposed.evaluate(std::vector<Eigen::Affine3d>{*h.matrix}, p);
  if (const char* dir = std::getenv("FREEFORM_SURVEY_OUT")) {
    TriangleSoup soup = mesh.to_soup();
    soup.positions = p.raw();
    write_mesh(std::string(dir) + "/bunny-ear-k3-decomposed.off", soup);
  }
  const int torn = count_folded_edges(mesh, rest, p);
  std::printf("bunny ear, decomposed: %d folded edges, min sv %.3f\n", torn, min_singular_value(mesh, rest, p));
  EXPECT_GT(torn, 0);
  EXPECT_LT(min_singular_value(mesh, rest, p), 0.2);  // carried by the model: at least 0.4, above

  // The linear model still needs the decomposition to keep any detail: it is unchanged.
  s.edit.deformation = Deformation::Linear;
  const EditSolver linear(mesh, s.edit);
  ASSERT_NE(linear.multires(), nullptr);
  EXPECT_FALSE(linear.stats().multires->detail_by_model);
}

}  // namespace
