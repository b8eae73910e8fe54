// Piecewise boundary smoothness (issue 15): "smoothness.segments" in edit files, checked
// against the formula of docs/bcm.md on the GLOBAL operators (bcm/bcm_fixtures.h: cotan Laplacian
// and mixed areas of the whole mesh, Eigen SparseLU), not the library's local assembly.
#include "bcm/bcm_fixtures.h"
#include "freeform/bcm/boundary_band.h"
#include "freeform/common/error.h"
#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_report.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/mesh/traversal.h"
#include "freeform/mesh/generators.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fmt/core.h>

using namespace freeform;
using ::testing::HasSubstr;

namespace {

// A disk of radius 1 (14 rings): support r < 0.86, the inner disk r < 0.3 is the handle,
// lifted by 0.35; the free annulus between them bends up.
const Mesh& disk() {
  static const Mesh mesh = Mesh::from_soup(make_disk(14, 1.0));
  return mesh;
}

std::string edit_text(int order, const std::string& smoothness) {
  return fmt::format(R"({{"order": {}, "multiresolution": false,
    "support": {{"sphere": {{"center": [0, 0, 0], "radius": 0.86}}}},
    "handles": [{{"region": {{"sphere": {{"center": [0, 0, 0], "radius": 0.3}}}}, "transform": {{"translate": [0, 0, 0.35]}}}}],
    "smoothness": {}}})",
                     order, smoothness);
}

// The outer boundary near +x is a crease (value c), the rest keeps outer = k-1.
std::string crease_segment(double c) {
  return fmt::format(R"({{"segments": [{{"region": {{"sphere": {{"center": [0.86, 0, 0], "radius": 0.45}}}}, "value": {}}}]}})", c);
}

Edit parse(const std::string& text) { return parse_edit_text(text, disk(), "edit.json", "."); }

std::string error(const std::string& text) {
  try {
    parse(text);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The free rows of deform(), in free-vertex order.
Eigen::MatrixXd free_rows(const Mesh& deformed, const Regions& regions) {
  Eigen::MatrixXd out(regions.n_free(), 3);
  for (int i = 0; i < regions.n_free(); ++i)
    out.row(i) = deformed.position(regions.free_vertices()[static_cast<std::size_t>(i)]).transpose();
  return out;
}

double diagonal(const Mesh& mesh) {
  Vec3 lo = mesh.position(Vertex(0)), hi = lo;
  for (Vertex v : mesh.vertices()) {
    lo = lo.cwiseMin(mesh.position(v));
    hi = hi.cwiseMax(mesh.position(v));
  }
  return (hi - lo).norm();
}

}  // namespace

TEST(SmoothnessSegments, CreaseStretchMatchesTheGlobalOperatorSolve) {
  const double diag = diagonal(disk());
  struct Case {
    int order;
    double c, tolerance;
    bool symmetric;
  };
  for (const Case& t : {Case{2, 0.0, 1e-7, true}, Case{3, 0.0, 1e-5, true}, Case{3, 1.0, 1e-5, false}}) {
    SCOPED_TRACE(fmt::format("k = {}, c = {}", t.order, t.c));
    const Edit edit = parse(edit_text(t.order, crease_segment(t.c)));
    ASSERT_EQ(edit.settings.smoothness.segments.size(), 1u);
    const Regions regions = edit_regions(disk(), edit);
    EditStats stats;
    const Mesh got = deform(disk(), edit, &stats);
    const Eigen::Affine3d lift(Eigen::Translation3d(0, 0, 0.35));
    const Eigen::MatrixXd want = test::reference_solve(disk(), regions, edit.settings, {lift});
    const Eigen::MatrixXd result = free_rows(got, regions);
    EXPECT_LT((result - want).cwiseAbs().maxCoeff(), t.tolerance * diag);
    // The solver follows the symmetry check: c = 1 at k = 3 makes lambda_1 != lambda_2.
    EXPECT_EQ(stats.bcm.symmetric, t.symmetric) << stats.bcm.solver;
    // The report names the segment (vertices kept, value).
    const EditSolver solver(disk(), edit);
    const Json report = edit_report(solver, {}, {});
    ASSERT_EQ(report["smoothness"]["segments"].size(), 1u);
    EXPECT_EQ(report["smoothness"]["segments"][0]["vertices"], edit.settings.smoothness.segments[0].vertices.size());
    EXPECT_EQ(report["smoothness"]["segments"][0]["value"], t.c);
    // The key is not ignored: uniform smoothness gives a visibly different surface.
    const Edit uniform = parse(edit_text(t.order, "{}"));
    EXPECT_GT((free_rows(deform(disk(), uniform), regions) - result).cwiseAbs().maxCoeff(), 0.01 * diag);
  }
}

TEST(SmoothnessSegments, KeepOnlyTheBandAndLaterSegmentsWin) {
  // k = 3: the band is the two rings of fixed vertices outside the support and the two rings
  // of handle vertices inside it.
  const Edit e = parse(edit_text(3, R"({"outer": 2, "segments": [
      {"region": {"sphere": {"center": [0, 0, 0], "radius": 2}}, "value": 0.5},
      {"region": {"sphere": {"center": [-0.86, 0, 0], "radius": 0.3}}, "value": 1.5}]})"));
  const Regions regions = edit_regions(disk(), e);
  const std::vector<Vertex> band = smoothness_band(disk(), regions, 3);
  ASSERT_EQ(e.settings.smoothness.segments.size(), 2u);
  EXPECT_EQ(e.settings.smoothness.segments[0].vertices, band);  // the whole mesh, cut to the band
  const VertexData<int> rings = ring_distance(disk(), regions.free_vertices(), 3);
  for (Vertex v : band) {
    EXPECT_NE(regions.role(v), Role::Free);
    EXPECT_TRUE(rings[v] == 1 || rings[v] == 2) << v.idx();
  }
  const std::vector<double> c = smoothness_per_vertex(regions, e.settings);
  int later = 0;
  for (Vertex v : e.settings.smoothness.segments[1].vertices) {
    EXPECT_EQ(c[static_cast<std::size_t>(v.idx())], 1.5);
    ++later;
  }
  EXPECT_GT(later, 0);
  for (Vertex v : regions.free_vertices()) EXPECT_EQ(c[static_cast<std::size_t>(v.idx())], 2.0);
}

TEST(SmoothnessSegments, ExportRoundTripIsExact) {
  for (int k : {2, 3}) {
    const Edit e = parse(edit_text(k, R"({"inner": 0.5, "segments": [
        {"region": {"sphere": {"center": [0.86, 0, 0], "radius": 0.45}}, "value": 0},
        {"region": {"geodesic": {"center": [0, 0.3, 0], "radius": 0.25}}, "value": 0.25}]})"));
    const Edit back = parse_edit(edit_to_json(e), disk(), "exported.json", ".");
    EXPECT_EQ(back.settings.smoothness.segments, e.settings.smoothness.segments);
    const Mesh a = deform(disk(), e), b = deform(disk(), back);
    for (Vertex v : disk().vertices()) ASSERT_EQ(a.position(v), b.position(v)) << v.idx();
  }
}

TEST(SmoothnessSegments, MalformedSegmentsNameTheSegment) {
  const std::string ok_region = R"({"sphere": {"center": [0.86, 0, 0], "radius": 0.45}})";
  const auto seg = [&](const std::string& body) { return edit_text(2, R"({"segments": [{"region": )" + ok_region + R"(, "value": 0}, )" + body + "]}"); };
  EXPECT_THAT(error(seg(R"({"region": )" + ok_region + R"(, "value": 1.5})")),
              HasSubstr("\"smoothness.segments[1].value\" must be in [0, 1] for order 2"));
  EXPECT_THAT(error(seg(R"({"region": )" + ok_region + R"(, "value": -0.1})")), HasSubstr("segments[1].value"));
  EXPECT_THAT(error(seg(R"({"region": )" + ok_region + "}")), HasSubstr("segments[1]"));
  EXPECT_THAT(error(seg(R"({"value": 0})")), HasSubstr("segments[1]"));
  EXPECT_THAT(error(seg(R"({"region": )" + ok_region + R"(, "value": 0, "c": 1})")), HasSubstr("segments[1].c"));
  EXPECT_THAT(error(seg(R"({"region": )" + ok_region + R"(, "value": "C0"})")), HasSubstr("segments[1].value"));
  // Only free vertices (the middle of the annulus): nothing where smoothness acts.
  EXPECT_THAT(error(seg(R"({"region": {"sphere": {"center": [0.55, 0, 0], "radius": 0.08}}, "value": 0})")),
              HasSubstr("\"smoothness.segments[1].region\" selects no constrained vertex where boundary smoothness acts"));
  EXPECT_THAT(error(seg(R"({"region": {"sphere": {"center": [5, 5, 5], "radius": 0.1}}, "value": 0})")),
              HasSubstr("segments[1].region"));
  EXPECT_THAT(error(seg(R"({"region": {"vertices": [100000]}, "value": 0})")), HasSubstr("segments[1].region"));
  EXPECT_THAT(error(edit_text(2, R"({"segments": {"region": {"vertices": [0]}, "value": 0}})")),
              HasSubstr("smoothness.segments"));
  // k = 1: a membrane is always C0.
  EXPECT_THAT(error(edit_text(1, R"({"segments": [{"region": )" + ok_region + R"(, "value": 0}]})")),
              HasSubstr("order 1 is always C0"));
  EXPECT_EQ(error(seg(R"({"region": )" + ok_region + R"(, "value": 1})")), "");
}
