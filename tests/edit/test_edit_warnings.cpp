// edit_warnings (edit/edit_report.h): one sentence per thing a user should know, the same list
// in the report's "warnings" (so in Python's solver.stats); none for a clean edit.
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_report.h"
#include "freeform/mesh/generators.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

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
