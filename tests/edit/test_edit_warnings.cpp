// edit_warnings (edit/edit_report.h): one sentence per thing a user should know, the same list
// in the report's "warnings" (so in Python's solver.stats); none for a clean edit.
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_report.h"
#include "freeform/mesh/generators.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <string>
#include <vector>

using namespace freeform;
using ::testing::HasSubstr;
using ::testing::Not;

namespace {

Edit plane_edit(const Mesh& mesh, const std::string& extra) {
  return parse_edit_text(R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.31}},
                             "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.11}},
                                          "transform": {"translate": [0, 0, 0.2],
                                                        "rotate": {"axis": [1, 0, 0], "degrees": 150}}}])" +
                             extra + "}",
                         mesh, "test", ".");
}

}  // namespace

TEST(EditWarnings, NoneForACleanEdit) {
  const Mesh mesh = Mesh::from_soup(make_plane(20, 20));
  const Edit edit = parse_edit_text(R"({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.31}},
      "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.11}},
                   "transform": {"translate": [0, 0, 0.05]}}]})",
                                    mesh, "test", ".");
  const EditSolver solver(mesh, edit);
  VertexData<Vec3> positions = mesh.positions();
  solver.evaluate(solver.transforms(edit), positions);
  EXPECT_TRUE(edit_warnings(solver, solver.problems(positions), solver.nonlinear_state()).empty());
  EXPECT_TRUE(edit_report(solver, {}, solver.problems(positions))["warnings"].empty());
}

TEST(EditWarnings, ACappedNonlinearRunAndTheFrameProblemsAreNamed) {
  const Mesh mesh = Mesh::from_soup(make_plane(20, 20));
  const Edit edit = plane_edit(mesh, R"(, "deformation": "nonlinear", "nonlinear": {"max_iterations": 1})");
  const EditSolver solver(mesh, edit);
  VertexData<Vec3> positions = mesh.positions();
  solver.evaluate(solver.transforms(edit), positions);
  ASSERT_FALSE(solver.nonlinear_state()->converged);
  EditProblems problems;
  problems.folded_edges = 3;
  problems.detail.flipped = 2;
  const std::vector<std::string> w = edit_warnings(solver, problems, solver.nonlinear_state());
  ASSERT_EQ(w.size(), 3u);
  EXPECT_THAT(w[0], HasSubstr("stopped at its cap of 1 iterations"));
  EXPECT_THAT(w[1], HasSubstr("3 folded edges"));
  EXPECT_THAT(w[2], HasSubstr("2 detail triangles flipped"));
  // Without a nonlinear state (the editor's panel) and frame problems: the precompute's only.
  EXPECT_TRUE(edit_warnings(solver).empty());
  const Json report = edit_report(solver, {}, problems);
  ASSERT_EQ(report["warnings"].size(), 3u);
  EXPECT_EQ(report["warnings"][0].get<std::string>(), w[0]);
  // At the cap the result is the iterate with the smallest step: within the tolerance where the
  // iteration cycled around it, which the warning must not call a larger residual.
  NonlinearState cycled = *solver.nonlinear_state();
  cycled.step = 0.5 * solver.nonlinear_options()->tolerance;
  const std::vector<std::string> c = edit_warnings(solver, {}, &cycled);
  ASSERT_EQ(c.size(), 1u);
  EXPECT_THAT(c[0], HasSubstr("cycled around the result"));
  EXPECT_THAT(c[0], Not(HasSubstr("> tolerance")));
}

TEST(EditWarnings, TheAnisotropicFallbackIsNamed) {
  // A closed sphere's whole surface grown by k rings has no boundary to map to the plane.
  const Mesh sphere = Mesh::from_soup(make_icosphere(2));
  const Edit edit = parse_edit_text(R"({"support": {"sphere": {"center": [0, 0, 0], "radius": 2}},
      "handles": [{"region": {"sphere": {"center": [0, 0, 1], "radius": 0.3}}, "transform": {"translate": [0, 0, 0.1]}},
                  {"region": {"sphere": {"center": [0, 0, -1], "radius": 0.3}}, "fixed": true}],
      "anisotropic": true, "multiresolution": false})",
                                    sphere, "test", ".");
  const EditSolver solver(sphere, edit);
  ASSERT_FALSE(solver.stats().bcm.anisotropic);
  const std::vector<std::string> w = edit_warnings(solver);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_THAT(w[0], HasSubstr("anisotropic bending fell back to the isotropic operator"));
}

// A 21 x 21 plane cut along x = 0.5 as files split their vertices along texture seams: the
// column there twice, the left faces on one copy, the right faces on the other. A support across
// the cut opens it (the two copies are solved apart), and the warning says where.
TEST(EditWarnings, AnOpenSeamInTheSupportIsNamed) {
  constexpr int n = 21, cut = 10;
  TriangleSoup soup;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) soup.positions.emplace_back(i / double(n - 1), j / double(n - 1), 0.0);
  for (int j = 0; j < n; ++j) soup.positions.push_back(soup.positions[static_cast<std::size_t>(j * n + cut)]);
  const auto at = [&](int i, int j, bool right) { return i == cut && right ? n * n + j : j * n + i; };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const bool right = i >= cut;
      soup.faces.push_back({at(i, j, right), at(i + 1, j, right), at(i + 1, j + 1, right)});
      soup.faces.push_back({at(i, j, right), at(i + 1, j + 1, right), at(i, j + 1, right)});
    }
  const Mesh mesh = Mesh::from_soup(soup);
  const Edit edit = parse_edit_text(R"({"support": {"sphere": {"center": [0.4, 0.5, 0], "radius": 0.31}},
      "handles": [{"region": {"sphere": {"center": [0.4, 0.5, 0], "radius": 0.11}},
                   "transform": {"translate": [0, 0, 0.05]}}]})",
                                    mesh, "test", ".");
  const EditSolver solver(mesh, edit);
  const std::array<Vertex, 2> pair = solver.stats().open_seam_example;
  EXPECT_EQ(mesh.position(pair[0]), mesh.position(pair[1]));
  EXPECT_NE(pair[0], pair[1]);
  VertexData<Vec3> positions = mesh.positions();
  solver.evaluate(solver.transforms(edit), positions);
  const std::vector<std::string> warnings = edit_warnings(solver, solver.problems(positions));
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_THAT(warnings[0],
              HasSubstr(std::to_string(solver.stats().open_seam_vertices) + " free vertices lie on an open seam"));
  EXPECT_THAT(warnings[0],
              HasSubstr("(e.g. " + std::to_string(pair[0].idx()) + " and " + std::to_string(pair[1].idx()) + ")"));
  // 0.31 about x = 0.4 reaches the cut at rows 0.25 .. 0.75, both copies free but at 0.5 (the
  // handle's).
  EXPECT_EQ(solver.stats().open_seam_vertices, 20);
  EXPECT_GT((positions[Vertex(8 * n + cut)] - positions[Vertex(n * n + 8)]).norm(), 1e-3);  // it opened at 0.4
}
