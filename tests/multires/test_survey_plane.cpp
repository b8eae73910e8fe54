// The bumpy-plane test of Botsch & Sorkine's deformation survey (docs/multires.md), rebuilt
// from its description: a 201 x 201 grid on a 100 x 100 square with 13 smooth bumps 10 units
// tall, the strip x <= 20 fixed, the far strip x >= 80 translated by (-32, 0, 57) so the plane
// bends into an S. Judged per edge and per bump against independent measurements: folded
// edges (dihedral angle grown by more than 60 degrees, computed here), and the apex heights
// along the normals of the smooth base (the same edit of the plane without bumps).
// FREEFORM_SURVEY_OUT=DIR writes the meshes and .sel/.def files for rendering.
#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"
#include "freeform/regions/sel_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <string>
#include <vector>

using namespace freeform;

namespace {

constexpr double kHeight = 10.0, kRadius = 10.0;
constexpr double kFixed = 10.0, kHandle = 90.0;  // x <= kFixed fixed, x >= kHandle the handle

// Bump centres: a 5 x 5 checkerboard over the square (13 cells), 3 in the fixed strip, 3 in
// the handle strip, 7 in the free part.
std::vector<Eigen::Vector2d> bump_centres() {
  std::vector<Eigen::Vector2d> c;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      if ((i + j) % 2 == 0) c.emplace_back(kFixed + kRadius + 15.0 * i, 10.0 + 20.0 * j);
  return c;
}

double bump(double r) { return r < kRadius ? 0.5 * kHeight * (1.0 + std::cos(std::numbers::pi * r / kRadius)) : 0.0; }

struct Survey {
  Mesh mesh;
  Edit edit;
  std::vector<Vertex> apexes;  // the free bumps' centre vertices
};

Survey survey(int order, bool multiresolution, bool bumps = true, const Vec3& move = Vec3(-32, 0, 57)) {
  TriangleSoup soup = make_plane(200, 200, 100.0, 100.0);
  for (Vec3& p : soup.positions)
    for (const Eigen::Vector2d& c : bump_centres()) p.z() += bumps ? bump((p.head<2>() - c).norm()) : 0.0;
  Survey s{Mesh::from_soup(soup), {}, {}};
  s.edit.settings.order = order;
  s.edit.multiresolution = multiresolution;
  EditHandle handle;
  for (Vertex v : s.mesh.vertices()) {
    const double x = s.mesh.position(v).x();
    if (x > kFixed + 1e-9) s.edit.support.push_back(v);
    if (x > kHandle - 1e-9) handle.vertices.push_back(v);
  }
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  t.translation() = move;
  handle.matrix = t;
  s.edit.handles.push_back(handle);
  for (const Eigen::Vector2d& c : bump_centres()) {
    const int i = static_cast<int>(std::lround(c.x() / 0.5)), j = static_cast<int>(std::lround(c.y() / 0.5));
    s.apexes.push_back(Vertex(j * 201 + i));
  }
  return s;
}

// Independent of mesh/folds.h: the angle between the normals of the two faces of every
// interior edge, from the face list.
std::vector<double> dihedral_angles(const TriangleSoup& soup, const std::vector<Vec3>& p) {
  std::vector<Vec3> n;
  for (const auto& f : soup.faces) n.push_back((p[f[1]] - p[f[0]]).cross(p[f[2]] - p[f[0]]).normalized());
  std::map<std::pair<int, int>, std::vector<int>> faces_of_edge;
  for (std::size_t f = 0; f < soup.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = soup.faces[f][k], b = soup.faces[f][(k + 1) % 3];
      faces_of_edge[{std::min(a, b), std::max(a, b)}].push_back(static_cast<int>(f));
    }
  std::vector<double> out;
  for (const auto& [e, fs] : faces_of_edge)
    if (fs.size() == 2) out.push_back(std::acos(std::clamp(n[fs[0]].dot(n[fs[1]]), -1.0, 1.0)) * 180.0 / std::numbers::pi);
  return out;
}

int folded_edges(const Mesh& rest, const Mesh& deformed) {
  const TriangleSoup soup = rest.to_soup();
  const std::vector<double> a = dihedral_angles(soup, rest.positions().raw());
  const std::vector<double> b = dihedral_angles(soup, deformed.positions().raw());
  int folded = 0;
  for (std::size_t i = 0; i < a.size(); ++i) folded += !(b[i] - a[i] <= 60.0);
  return folded;
}

// Height of vertex v above the base along the base's area-weighted vertex normal at v.
double height(const Mesh& mesh, const Mesh& base, const Mesh& detailed, Vertex v) {
  Vec3 n = Vec3::Zero();
  for (Face f : mesh.faces()) {
    const auto h = mesh.halfedges(f);
    const Vertex a = mesh.from_vertex(h[0]), b = mesh.to_vertex(h[0]), c = mesh.to_vertex(h[1]);
    if (a != v && b != v && c != v) continue;
    n += (base.position(b) - base.position(a)).cross(base.position(c) - base.position(a));
  }
  return (detailed.position(v) - base.position(v)).dot(n.normalized());
}

void write_for_rendering(const Survey& s, const Mesh& out, const std::string& name) {
  const char* dir = std::getenv("FREEFORM_SURVEY_OUT");
  if (!dir) return;
  write_mesh(std::string(dir) + "/survey-rest.off", s.mesh.to_soup());
  TriangleSoup soup = s.mesh.to_soup();
  soup.positions = out.positions().raw();
  write_mesh(std::string(dir) + "/" + name + ".off", soup);
  std::ofstream sel(std::string(dir) + "/survey.sel");
  for (Vertex v : s.mesh.vertices()) {
    const double x = s.mesh.position(v).x();
    sel << (x > kHandle - 1e-9 ? 2 : x > kFixed + 1e-9 ? 1 : 0) << "\n";
  }
  std::ofstream def(std::string(dir) + "/survey.def");
  def << "1 0 0 -32\n0 1 0 0\n0 0 1 57\n0 0 0 1\n";
}

// The heights as the paper defines detail (Botsch & Kobbelt 2004, section 5): the apex's offset
// along the vertex normal of the BCM base, the k-harmonic solve of the bumpy plane's support with
// the same k, smoothness and handle transform, before (identity) and after the edit. The base is
// solved here with multiresolution off (BcmSolver: a direct solve, validated against CGAL's
// fair and closed forms in tests/references), not through the multiresolution code; the
// normals are area weighted, computed here.
struct Smoothness {
  int order;
  double c;  // outer and inner boundary smoothness C^c
};

class SurveyPlaneHeights : public ::testing::TestWithParam<Smoothness> {};

Survey with_smoothness(Survey s, double c) {
  s.edit.settings.smoothness.outer = c;
  s.edit.settings.smoothness.inner = c;
  return s;
}

TEST_P(SurveyPlaneHeights, SBendKeepsTheBumpHeightsOnThePapersBaseWithoutFolds) {
  const auto [k, c] = GetParam();
  const Survey s = with_smoothness(survey(k, true), c);
  ASSERT_EQ(s.apexes.size(), 13u);
  const EditSolver solver(s.mesh, s.edit);
  Mesh out = s.mesh;
  solver.evaluate(solver.transforms(s.edit), out.positions());
  if (k == 3 && c == 2) write_for_rendering(s, out, "survey-k3");
  if (k == 2 && c == 1) write_for_rendering(s, out, "survey-k2");

  Survey plain = s;
  plain.edit.multiresolution = false;
  const Mesh base = deform(s.mesh, plain.edit);
  Edit unmoved = plain.edit;
  unmoved.handles[0].matrix = Eigen::Affine3d::Identity();
  const Mesh rest_base = deform(s.mesh, unmoved);

  // The result's smooth part is that base (to 0.5 % of the bump height).
  VertexData<Vec3> own_base = s.mesh.positions();
  solver.multires()->base_positions(own_base);
  double base_gap = 0;
  for (Vertex v : s.mesh.vertices()) base_gap = std::max(base_gap, (own_base[v] - base.position(v)).norm());
  EXPECT_LE(base_gap, 0.005 * kHeight) << "k = " << k << ", C" << c;

  std::vector<double> errors;
  for (Vertex a : s.apexes) {
    const double before = height(s.mesh, rest_base, s.mesh, a), after = height(s.mesh, base, out, a);
    errors.push_back(std::abs(after - before) / before);
  }
  std::sort(errors.begin(), errors.end());
  const int folded = folded_edges(s.mesh, out);
  std::printf("k=%d C%g: apex height error median %.2f%%, max %.2f%%; %d folded edges; base gap %.1e\n", k, c,
              100 * errors[errors.size() / 2], 100 * errors.back(), folded, base_gap);
  EXPECT_LE(errors[errors.size() / 2], 0.02) << "median apex height error, k = " << k << ", C" << c;
  EXPECT_LE(errors.back(), 0.05) << "max apex height error, k = " << k << ", C" << c;
  EXPECT_EQ(folded, 0) << "k = " << k << ", C" << c;
  EXPECT_EQ(solver.problems(out.positions()).folded_edges, folded);  // the library's metric agrees
}

INSTANTIATE_TEST_SUITE_P(OrdersAndSmoothness, SurveyPlaneHeights,
                         ::testing::Values(Smoothness{2, 1}, Smoothness{2, 0}, Smoothness{3, 2}, Smoothness{3, 1},
                                           Smoothness{3, 0}),
                         [](const ::testing::TestParamInfo<Smoothness>& p) {
                           return "k" + std::to_string(p.param.order) + "C" + std::to_string(static_cast<int>(p.param.c));
                         });

class SurveyPlane : public ::testing::TestWithParam<int> {};

// The same S-bend with the nonlinear model (docs/nonlinear.md): the base rotates with the bend,
// the detail rides along; the same bounds hold, the apex heights against the nonlinear bend of
// the flat plane.
TEST_P(SurveyPlane, NonlinearSBendKeepsTheBumpsWithoutFolds) {
  const int k = GetParam();
  Survey s = survey(k, true);
  s.edit.deformation = Deformation::Nonlinear;
  const EditSolver solver(s.mesh, s.edit);
  Mesh out = s.mesh;
  solver.evaluate(solver.transforms(s.edit), out.positions());
  ASSERT_TRUE(solver.nonlinear_state()->converged);
  EXPECT_FALSE(solver.stats().multires->detail_by_model);  // the bumps stand on their base: decomposed
  std::printf("nonlinear S-bend k=%d: %d iterations, %.0f ms\n", k, solver.nonlinear_state()->iterations,
              solver.nonlinear_state()->ms);
  Survey flat = survey(k, false, false);
  flat.edit.deformation = Deformation::Nonlinear;
  flat.edit.nonlinear.smooth_rest = true;  // the same model as on the bumpy plane's smooth base
  const Mesh base = deform(flat.mesh, flat.edit);
  write_for_rendering(s, out, "survey-nonlinear-k" + std::to_string(k));
  // Until 2026-11-26 k = 2 folded 28 edges here: a 15-degree kink at the fixed strip (edges
  // to the constrained ring turned with the mean of both ends' rotations) and a rotation fit
  // over too few rings for this resolution crumpled the first bumps (docs/nonlinear.md).
  EXPECT_EQ(folded_edges(s.mesh, out), 0) << "k = " << k;
  EXPECT_EQ(solver.problems(out.positions()).non_finite, 0);
  std::vector<double> errors;
  for (Vertex a : s.apexes) errors.push_back(std::abs(height(s.mesh, base, out, a) - kHeight) / kHeight);
  std::sort(errors.begin(), errors.end());
  EXPECT_LE(errors[errors.size() / 2], 0.02) << "median apex height error, k = " << k;
  EXPECT_LE(errors.back(), 0.05) << "max apex height error, k = " << k;
}

// The bare plane's nonlinear S-bend is as smooth as linear BCM's: no crease anywhere, also
// not where it leaves the fixed strip (there the boundary is C^(k-1), as in linear BCM).
TEST_P(SurveyPlane, NonlinearSBendHasNoKinkAtTheFixedStrip) {
  const int k = GetParam();
  const Survey linear = survey(k, false, false);
  Survey nonlinear = linear;
  nonlinear.edit.deformation = Deformation::Nonlinear;
  const TriangleSoup soup = linear.mesh.to_soup();
  const std::vector<double> a = dihedral_angles(soup, deform(linear.mesh, linear.edit).positions().raw());
  const std::vector<double> b = dihedral_angles(soup, deform(nonlinear.mesh, nonlinear.edit).positions().raw());
  const double max_linear = *std::max_element(a.begin(), a.end());
  const double max_nonlinear = *std::max_element(b.begin(), b.end());
  std::printf("k=%d largest dihedral angle: linear %.2f, nonlinear %.2f degrees\n", k, max_linear, max_nonlinear);
  // Measured 2.24 / 1.65 (k = 2), 2.18 / 1.86 (k = 3) since the spokes-and-rims membrane, whose
  // edges to the constraints turn with the mean of both ends (2.01 / 2.12 before); the kink
  // was 15 degrees in one edge.
  EXPECT_LE(max_nonlinear, 1.4 * max_linear) << "k = " << k;
}

// A bend tighter than the bumps are tall (the bottom of the S has a radius of curvature below
// 10 under the first row of bumps): the detail cannot keep its height there without folding.
// What folds stays local and is reported (folded edges, flipped detail triangles), nothing is
// thrown away from the base (no spikes), nothing is non-finite.
TEST_P(SurveyPlane, TooTightABendStaysLocalAndIsReported) {
  const int k = GetParam();
  const Vec3 move(-55, 0, 60);
  const Survey s = survey(k, true, true, move);
  const EditSolver solver(s.mesh, s.edit);
  Mesh out = s.mesh;
  solver.evaluate(solver.transforms(s.edit), out.positions());
  const EditProblems problems = solver.problems(out.positions());
  const int folded = folded_edges(s.mesh, out);
  std::printf("tight S-bend k=%d: %d folded edges, %d flipped detail triangles\n", k, folded, problems.detail.flipped);
  EXPECT_EQ(problems.non_finite, 0);
  EXPECT_EQ(problems.folded_edges, folded);
  EXPECT_GT(problems.detail.flipped, 0) << "the folded detail is counted";
  EXPECT_LT(folded, static_cast<int>(solver.touched().size()) / 500) << "and stays local";
  Survey flat = survey(k, false, false, move);
  const Mesh base = deform(flat.mesh, flat.edit);
  double farthest = 0;
  for (Vertex v : solver.touched()) farthest = std::max(farthest, (out.position(v) - base.position(v)).norm());
  EXPECT_LE(farthest, 1.5 * kHeight) << "a spike: a vertex far off its base (the bumps are kHeight tall)";
}

INSTANTIATE_TEST_SUITE_P(Orders, SurveyPlane, ::testing::Values(2, 3));

}  // namespace
