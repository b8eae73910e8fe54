// Undo/redo: transitions replay exactly both ways, the stacks behave, steps cost memory in
// proportion to what changed, and a random session of mixed Document operations is restored
// bit for bit by undoing everything and redoing everything.
#include "editor/document.h"
#include "editor_test_util.h"
#include "editor/history.h"

#include "freeform/mesh/generators.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

namespace freeform::editor {
namespace {

using test_util::disc;

EditState random_state(int n, int first_id, std::mt19937& rng) {
  EditState s(n);
  std::uniform_int_distribution<int> vd(0, n - 1), bd(0, 1);
  for (int i = 0; i < 3; ++i) s.insert_handle(i, HandleState{first_id + i, i != 1, {}, {}});
  for (int k = 0; k < n / 2; ++k) {
    const int h = std::uniform_int_distribution<int>(-3, 2)(rng);
    s.set_vertex(Vertex(vd(rng)), bd(rng) == 1, h < 0 ? -1 : first_id + h);
  }
  Manipulator m;
  m.translation = Vec3(0.1 * bd(rng), 0.2, 0.0);
  m.pivot = Vec3(0.5, 0.5, 0.0);
  s.set_transform(first_id, m, std::nullopt);
  return s;
}

TEST(History, TransitionsPlayBothWaysExactly) {
  std::mt19937 rng(3);
  const int n = 300;
  const EditState a = random_state(n, 0, rng);
  EditState b = random_state(n, 3, rng);  // all handles new
  EditParameters p;
  p.settings.order = 2;
  b.set_parameters(p);
  for (const EditState* to : {&b}) {
    const Step step = make_transition(a, *to, "t");
    EditState s = a;
    for (const Delta& d : step.deltas) play(d, s, true);
    EXPECT_TRUE(s == *to);
    for (auto it = step.deltas.rbegin(); it != step.deltas.rend(); ++it) play(*it, s, false);
    EXPECT_TRUE(s == a);
  }
  // Kept handles: delete one, move another.
  EditState c = a;
  for (Vertex v : c.handle_vertices(1)) c.set_vertex(v, false, -1);
  c.erase_handle(1);
  Manipulator m;
  m.scale = Vec3(2, 2, 2);
  m.pivot = Vec3::Zero();
  c.set_transform(2, m, std::nullopt);
  const Step step = make_transition(a, c, "t");
  EditState s = a;
  for (const Delta& d : step.deltas) play(d, s, true);
  EXPECT_TRUE(s == c);
  for (auto it = step.deltas.rbegin(); it != step.deltas.rend(); ++it) play(*it, s, false);
  EXPECT_TRUE(s == a);
}

TEST(History, RegionRecorderKeepsFirstOldValueAndDropsReverted) {
  EditState s(10);
  s.insert_handle(0, HandleState{5, true, {}, {}});
  s.set_vertex(Vertex(2), true, -1);
  RegionRecorder rec;
  const auto change = [&](int v, bool sup, int h) {
    rec.touch(Vertex(v), s);
    s.set_vertex(Vertex(v), sup, h);
  };
  change(1, true, -1);
  change(1, false, 5);  // the old value stays the first one
  change(2, false, -1);
  change(2, true, -1);  // back where it was: dropped
  change(3, true, 5);
  std::vector<int> touched;
  const RegionDelta d = rec.finish(s, &touched);
  ASSERT_EQ(d.changes.size(), 2u);
  EXPECT_EQ(d.changes[0].vertex, 1);
  EXPECT_FALSE(d.changes[0].old_support);
  EXPECT_EQ(d.changes[0].old_handle, -1);
  EXPECT_EQ(d.changes[0].new_handle, 5);
  EXPECT_EQ(d.changes[1].vertex, 3);
  EXPECT_EQ(touched, std::vector<int>{5});
  EditState back = s;
  play(d, back, false);
  EditState expected(10);
  expected.insert_handle(0, HandleState{5, true, {}, {}});
  expected.set_vertex(Vertex(2), true, -1);
  EXPECT_TRUE(back == expected);
}

TEST(History, StacksAndMemory) {
  History h;
  const auto region_step = [](int changes) {
    RegionDelta r;
    for (int i = 0; i < changes; ++i) r.changes.push_back({i, -1, -1, false, true});
    return Step{"paint", {Delta(std::move(r))}};
  };
  h.push(region_step(1));
  const std::size_t one = h.memory_bytes();
  h.push(region_step(1001));
  const std::size_t big = h.memory_bytes() - one;
  // O(changed vertices): 1000 more changes cost ~1000 * sizeof(VertexChange).
  EXPECT_GE(big - one, 1000 * sizeof(VertexChange));
  EXPECT_LE(big - one, 1100 * sizeof(VertexChange));
  EXPECT_EQ(h.undo().deltas.size(), 1u);
  EXPECT_TRUE(h.can_redo());
  EXPECT_EQ(h.memory_bytes(), one + big);  // kept for redo
  h.push(region_step(2));                  // a new step clears the redo stack
  EXPECT_FALSE(h.can_redo());
  EXPECT_EQ(h.undo_size(), 2u);
  EXPECT_LT(h.memory_bytes(), one + big);
  h.push(Step{"empty", {}});
  EXPECT_EQ(h.undo_size(), 2u);
  h.set_memory_limit(one + 10);  // the oldest steps go, the newest stays
  EXPECT_EQ(h.undo_size(), 1u);
  EXPECT_LE(h.memory_bytes(), one + 10 + 2 * sizeof(VertexChange));
}

TEST(History, OneVertexPaintCostsFarLessThanTheMesh) {
  Document doc;
  doc.open_mesh(Mesh::from_soup(make_plane(100, 100)));  // 10201 vertices
  const std::size_t before = doc.history().memory_bytes();
  const Vertex v(5000);
  doc.set_region(PaintMode::Support, std::span<const Vertex>(&v, 1), false);
  const std::size_t step = doc.history().memory_bytes() - before;
  EXPECT_GT(step, 0u);
  EXPECT_LT(step, static_cast<std::size_t>(doc.rest_mesh().n_vertices()) / 4);  // a per-vertex byte array is #V
}

struct Snapshot {
  EditState state;
  std::vector<Vec3> rest;
  std::size_t applied = 0;
};

Snapshot snap(const Document& d) {
  return {d.state(), d.rest_mesh().positions().raw(), d.applied_edits().size()};
}

void expect_same(const Snapshot& a, const Snapshot& b, const std::string& where) {
  EXPECT_TRUE(a.state == b.state) << where;
  ASSERT_EQ(a.rest.size(), b.rest.size());
  EXPECT_EQ(std::memcmp(a.rest.data(), b.rest.data(), a.rest.size() * sizeof(Vec3)), 0) << where;
  EXPECT_EQ(a.applied, b.applied) << where;
}

TEST(History, RandomSessionUndoesAndRedoesExactly) {
  Document doc;
  doc.open_mesh(Mesh::from_soup(make_bumpy_plane(12, 12, 0.05, 2.0)));
  const Mesh& m0 = doc.rest_mesh();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Snapshot> snaps{snap(doc)};
  int applies = 0;
  // A valid start so Apply has something to bake.
  doc.set_region(PaintMode::Support, disc(m0, Vec3(0.5, 0.5, 0), 0.4), false);
  snaps.push_back(snap(doc));
  doc.set_region(PaintMode::Handle, disc(m0, Vec3(0.5, 0.5, 0), 0.1), false);
  snaps.push_back(snap(doc));
  for (int op = 0; op < 50; ++op) {
    const Vec3 c(u(rng), u(rng), 0);
    const int kind = std::uniform_int_distribution<int>(0, 9)(rng);
    const auto verts = disc(doc.rest_mesh(), c, 0.05 + 0.15 * u(rng));
    switch (kind) {
      case 0: case 1: doc.set_region(PaintMode::Support, verts, kind == 1); break;
      case 2: doc.set_region(PaintMode::Handle, verts, false); break;
      case 3: doc.set_region(PaintMode::Immovable, verts, u(rng) < 0.3); break;
      case 4: doc.new_handle(u(rng) < 0.7); break;
      case 5:
        if (!doc.state().handles().empty())
          doc.delete_handle(doc.state().handles()[static_cast<std::size_t>(u(rng) * doc.state().handles().size())].id);
        break;
      case 6: {
        EditParameters p = doc.parameters();
        p.settings.order = 1 + static_cast<int>(u(rng) * 3);
        p.settings.smoothness.outer = 2.0 * u(rng);
        p.multiresolution = u(rng) < 0.5;
        doc.set_parameters(p);
        break;
      }
      case 7: case 8: {
        for (const HandleState& h : doc.state().handles()) {
          if (!h.movable) continue;
          const Manipulator start = h.manipulator;  // preview changes h
          Manipulator m = start;
          m.translation += Vec3(0.1 * u(rng), 0.0, 0.2 * u(rng));
          m.rotation = Manipulator::axis_angle(Vec3(u(rng), 1.0, 0.5), 40.0 * u(rng));
          doc.preview_manipulator(h.id, m);
          doc.commit_manipulator(h.id, start, m);
          break;
        }
        break;
      }
      case 9: {
        std::vector<int> empty;
        for (const HandleState& h : doc.state().handles())
          if (doc.state().handle_size(h.id) == 0) empty.push_back(h.id);
        for (int id : empty) {  // one step each
          doc.delete_handle(id);
          snaps.push_back(snap(doc));
        }
        doc.wait_for_precompute();
        if (doc.apply_blocker().empty()) {
          doc.apply();
          ++applies;
        }
        break;
      }
    }
    if (doc.history().undo_size() + 1 > snaps.size()) snaps.push_back(snap(doc));
    ASSERT_EQ(doc.history().undo_size() + 1, snaps.size());
  }
  EXPECT_GE(applies, 1);
  EXPECT_GE(snaps.size(), 30u);
  for (std::size_t i = snaps.size() - 1; i-- > 0;) {
    doc.undo();
    expect_same(snap(doc), snaps[i], "undo to " + std::to_string(i));
  }
  EXPECT_FALSE(doc.can_undo());
  for (std::size_t i = 1; i < snaps.size(); ++i) {
    doc.redo();
    expect_same(snap(doc), snaps[i], "redo to " + std::to_string(i));
  }
  EXPECT_FALSE(doc.can_redo());
  doc.wait_for_precompute();
}

}  // namespace
}  // namespace freeform::editor
