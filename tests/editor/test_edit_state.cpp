// EditState: counts against a brute-force recount, parameter clamping, problems, to_edit /
// from_edit / edit_to_json round trips, and the exact transform of a handle.
#include "editor/edit_state.h"
#include "editor_test_util.h"

#include "freeform/edit/edit_json.h"
#include "freeform/edit/edit_solver.h"
#include "freeform/common/error.h"
#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <random>

namespace freeform::editor {
namespace {

Mesh plane() { return Mesh::from_soup(make_bumpy_plane(14, 14, 0.05, 2.0)); }

using test_util::disc;

Manipulator some_manipulator() {
  Manipulator m;
  m.translation = Vec3(0.1, -0.05, 0.2);
  m.rotation = Manipulator::axis_angle(Vec3(1, 2, 3), 25.0);
  m.scale = Vec3(1.1, 0.9, 1.2);
  return m;
}

// A state with support, one movable handle (moved) and one immovable handle.
EditState sample(const Mesh& mesh) {
  EditState s(mesh.n_vertices());
  for (Vertex v : disc(mesh, Vec3(0.5, 0.5, 0), 0.4)) s.set_vertex(v, true, -1);
  HandleState a;
  a.id = 0;
  s.insert_handle(0, a);
  const auto va = disc(mesh, Vec3(0.5, 0.5, 0), 0.1);
  for (Vertex v : va) s.set_vertex(v, s.support_flag(v), 0);
  HandleState b;
  b.id = 1;
  b.movable = false;
  s.insert_handle(1, b);
  for (Vertex v : disc(mesh, Vec3(0.75, 0.5, 0), 0.06)) s.set_vertex(v, false, 1);  // outside-flag, still support
  Manipulator m = some_manipulator();
  m.pivot = centroid(mesh, va);
  s.set_transform(0, m, std::nullopt);
  return s;
}

TEST(EditState, CountsMatchBruteForceOverRandomEdits) {
  const Mesh mesh = plane();
  EditState s(mesh.n_vertices());
  for (int id = 0; id < 3; ++id) s.insert_handle(id, HandleState{id, id != 2, {}, {}});
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> vd(0, mesh.n_vertices() - 1), hd(-1, 2), bd(0, 1);
  for (int step = 0; step < 2000; ++step) s.set_vertex(Vertex(vd(rng)), bd(rng) == 1, hd(rng));
  int support = 0, in_handles = 0;
  std::vector<int> per(3, 0);
  for (Vertex v : mesh.vertices()) {
    const int h = s.handle_ids()[static_cast<std::size_t>(v.idx())];
    support += (s.support_flags()[static_cast<std::size_t>(v.idx())] != 0 || h >= 0) ? 1 : 0;
    if (h >= 0) ++per[static_cast<std::size_t>(h)], ++in_handles;
  }
  EXPECT_EQ(s.n_support(), support);
  EXPECT_EQ(s.n_handle_vertices(), in_handles);
  EXPECT_EQ(s.n_free(), support - in_handles);
  for (int id = 0; id < 3; ++id) {
    EXPECT_EQ(s.handle_size(id), per[static_cast<std::size_t>(id)]);
    EXPECT_EQ(static_cast<int>(s.handle_vertices(id).size()), per[static_cast<std::size_t>(id)]);
  }
  EXPECT_EQ(static_cast<int>(s.support_vertices().size()), support);
  EXPECT_THROW(s.set_vertex(Vertex(0), true, 9), InvalidInput);
  EXPECT_THROW(s.set_vertex(Vertex(mesh.n_vertices()), true, -1), InvalidInput);
  EXPECT_THROW(s.erase_handle(0), InvalidInput);  // still has vertices
}

TEST(EditState, ParametersClampWithOrder) {
  EditParameters p;
  p.settings.order = 2;
  const EditParameters n = normalized(p);  // 2.0 > k-1 = 1
  EXPECT_EQ(n.settings.smoothness.outer, 1.0);
  EXPECT_EQ(n.settings.smoothness.inner, 1.0);
  p.settings.order = 1;
  EXPECT_EQ(normalized(p).settings.smoothness.outer, 0.0);
  p.settings.order = 3;
  p.settings.smoothness.outer = 1.25;
  EXPECT_EQ(normalized(p).settings.smoothness.outer, 1.25);
  p.settings.order = 4;
  EXPECT_THROW(normalized(p), InvalidInput);
  p.settings.order = 3;
  p.settings.smoothness.inner = std::nan("");
  EXPECT_THROW(normalized(p), InvalidInput);
}

TEST(EditState, ProblemsSayWhatToPaint) {
  const Mesh mesh = plane();
  EditState s(mesh.n_vertices());
  EXPECT_NE(s.problem(mesh).find("paint a support region"), std::string::npos);
  s.insert_handle(0, HandleState{4, true, {}, {}});
  s.set_vertex(Vertex(100), true, -1);
  EXPECT_NE(s.problem(mesh).find("handle 4 has no vertices"), std::string::npos);
  s.set_vertex(Vertex(100), true, 4);
  EXPECT_NE(s.problem(mesh).find("all handle"), std::string::npos);
  const EditState ok = sample(mesh);
  EXPECT_EQ(ok.problem(mesh), "");
  EXPECT_NO_THROW((void)ok.regions(mesh));
}

TEST(EditState, TransformIsPivotRotateScaleTranslateThenMatrix) {
  const Mesh mesh = plane();
  EditState s = sample(mesh);
  Eigen::Matrix4d mm = Eigen::Matrix4d::Identity();
  mm.topLeftCorner<3, 3>() << 1, 0.2, 0, 0, 1, 0, 0, 0.1, 1.5;
  mm.topRightCorner<3, 1>() << 0.3, 0, -0.1;
  const HandleState h0 = *s.find_handle(0);
  s.set_transform(0, h0.manipulator, Eigen::Affine3d(mm));
  const Eigen::Affine3d t = s.transform(0, mesh);
  const Manipulator& m = h0.manipulator;
  const Eigen::Matrix3d r = m.rotation.normalized().toRotationMatrix();
  for (const Vec3& x : {Vec3(0, 0, 0), Vec3(1, 2, 3), Vec3(-0.5, 0.25, 2)}) {
    const Vec3 y = (mm * x.homogeneous()).head<3>();
    const Vec3 expected = *m.pivot + r * m.scale.cwiseProduct(y - *m.pivot) + m.translation;
    EXPECT_LT((t * x - expected).norm(), 1e-14);
  }
  // The identity manipulator leaves the matrix exactly.
  Manipulator id;
  id.pivot = Vec3(0.3, 0.2, 0.1);
  s.set_transform(0, id, Eigen::Affine3d(mm));
  EXPECT_TRUE(s.transform(0, mesh).matrix() == mm);
}

TEST(EditState, RecentredKeepsTheMap) {
  Manipulator m = some_manipulator();
  m.pivot = Vec3(0.2, 0.4, 0.0);
  const Manipulator r = recentred(m, Vec3(0.7, -0.3, 0.5));
  EXPECT_EQ(*r.pivot, Vec3(0.7, -0.3, 0.5));
  for (const Vec3& x : {Vec3(0, 0, 0), Vec3(1, 2, 3)})
    EXPECT_LT((m.to_affine(Vec3::Zero()) * x - r.to_affine(Vec3::Zero()) * x).norm(), 1e-14);
  Manipulator t;  // a pure translation keeps its translation exactly
  t.translation = Vec3(0.1, 0.2, 0.3);
  t.pivot = Vec3(1, 1, 1);
  EXPECT_EQ(recentred(t, Vec3(5, 6, 7)).translation, t.translation);
}

TEST(EditState, EditRoundTripsThroughJsonAndFromEdit) {
  const Mesh mesh = plane();
  EditState s = sample(mesh);
  EditParameters p;
  p.settings.order = 2;
  p.settings.smoothness.outer = 0.5;
  p.settings.anisotropic = true;
  p.multiresolution = false;
  p.deformation = Deformation::Nonlinear;
  p.nonlinear.preserve_volume = false;
  p.nonlinear.max_iterations = 250;
  p.nonlinear.tolerance = 3e-5;
  p.allow_unanchored = true;
  s.set_parameters(p);
  const Edit e = s.to_edit(mesh);
  EXPECT_EQ(e.deformation, Deformation::Nonlinear);
  EXPECT_FALSE(e.nonlinear.preserve_volume);
  EXPECT_EQ(e.nonlinear.max_iterations, 250);
  EXPECT_EQ(e.nonlinear.tolerance, 3e-5);
  EXPECT_TRUE(e.allow_unanchored);
  ASSERT_EQ(e.handles.size(), 2u);
  EXPECT_TRUE(e.handles[0].matrix.has_value());
  EXPECT_FALSE(e.handles[1].movable);
  EXPECT_EQ(e.support.size(), static_cast<std::size_t>(s.n_support()));

  const Edit back = parse_edit_text(json_text(edit_to_json(e)), mesh, "test", ".");
  EXPECT_EQ(back.support, e.support);
  ASSERT_EQ(back.handles.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(back.handles[i].vertices, e.handles[i].vertices);
    EXPECT_EQ(back.handles[i].movable, e.handles[i].movable);
  }
  EXPECT_TRUE(back.handles[0].matrix->matrix() == e.handles[0].matrix->matrix());  // bit for bit
  EXPECT_EQ(back.settings.order, 2);
  EXPECT_EQ(back.settings.smoothness.outer, 0.5);
  EXPECT_EQ(back.settings.smoothness.inner, 1.0);
  EXPECT_TRUE(back.settings.anisotropic);
  EXPECT_FALSE(back.multiresolution);
  EXPECT_FALSE(back.nonlinear.preserve_volume);
  EXPECT_EQ(back.nonlinear.max_iterations, 250);
  EXPECT_EQ(back.nonlinear.tolerance, 3e-5);
  EXPECT_TRUE(back.allow_unanchored);

  const EditState again = EditState::from_edit(back, mesh, 10);
  EXPECT_EQ(again.support_vertices(), s.support_vertices());
  EXPECT_EQ(again.parameters(), s.parameters());
  ASSERT_EQ(again.handles().size(), 2u);
  EXPECT_EQ(again.handles()[0].id, 10);
  EXPECT_EQ(again.handle_vertices(10), s.handle_vertices(0));
  EXPECT_FALSE(again.handles()[1].movable);
  EXPECT_TRUE(again.transform(10, mesh).matrix() == s.transform(0, mesh).matrix());
}

TEST(EditState, ImportedManipulatorUsesTheSolversDefaultPivot) {
  const Mesh mesh = plane();
  Edit e;
  e.settings.order = 2;
  e.multiresolution = false;
  e.support = disc(mesh, Vec3(0.5, 0.5, 0), 0.35);
  EditHandle h;
  h.vertices = disc(mesh, Vec3(0.5, 0.5, 0), 0.1);
  h.manipulator = some_manipulator();  // pivot unset: deform() uses the handle centroid
  e.handles.push_back(h);
  const EditState s = EditState::from_edit(e, mesh);
  const Mesh direct = deform(mesh, e);
  const Mesh replay = deform(mesh, s.to_edit(mesh));
  for (Vertex v : mesh.vertices()) EXPECT_EQ(direct.position(v), replay.position(v));
}

TEST(EditState, FromEditRefusesOverlappingHandles) {
  const Mesh mesh = plane();
  Edit e;
  e.support = {Vertex(1), Vertex(2), Vertex(3)};
  e.handles.push_back(EditHandle{{Vertex(2)}, true, {}, {}});
  e.handles.push_back(EditHandle{{Vertex(2), Vertex(3)}, false, {}, {}});
  try {
    (void)EditState::from_edit(e, mesh);
    FAIL() << "no error";
  } catch (const InvalidInput& err) {
    EXPECT_NE(std::string(err.what()).find("vertex 2 is in handles 0 and 1"), std::string::npos) << err.what();
  }
}

}  // namespace
}  // namespace freeform::editor
