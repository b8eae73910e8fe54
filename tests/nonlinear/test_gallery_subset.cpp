// A subset of the gallery (bench/bench_gallery.cpp, docs/nonlinear.md "Gallery"): the seeded limb
// edits of libcgal-demo's elephant (bends, twists, a pull and two limbs at once; 186-513 free
// vertices), the nonlinear model at k = 2 and 3 against CGAL's ARAP run in the same test.
// These bounds guard today's standing against the peer; they are not the goal (no more
// collapsed faces than ARAP), which the model does not meet yet.
#include "cgal_arap.h"
#include "gallery_cases.h"
#include "test_support.h"

#include "freeform/edit/edit_solver.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/folds.h"
#include "freeform/mesh/generators.h"
#include "freeform/multires/multires_solver.h"
#include "freeform/multires/operator_shape.h"
#include "freeform/nonlinear/nonlinear_solver.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <tuple>

using namespace freeform;
using namespace freeform::test;

namespace {

struct Quality {
  int folds = 0, collapsed = 0;
};

Quality quality(const Shape& s, const VertexData<Vec3>& p) {
  Quality q;
  q.folds = count_folded_edges(s.mesh, s.mesh.positions(), p);
  for (Face f : s.mesh.faces()) q.collapsed += face_min_singular_value(s.mesh, s.mesh.positions(), p, f) < 0.5;
  return q;
}

// The edits of one libcgal-demo mesh (`make`: one of gallery_cases.h's families), drawn as
// bench_gallery draws a mesh's (seed 37 for this mesh alone, so the angles are not the gallery's
// own); none when the mesh is missing (a failure where the meshes are required).
std::vector<Shape> mesh_limb_cases(const std::string& name, int limbs, double radius, int subdivisions = 0,
                                   CaseMaker make = limb_cases) {
  const std::filesystem::path file = cgal_mesh_dir().empty() ? "" : cgal_mesh_dir() / (name + ".off");
  if (file.empty() || !std::filesystem::exists(file)) {
    if (data_required()) ADD_FAILURE() << name << ".off missing: run scripts/fetch-data.sh";
    return {};
  }
  TriangleSoup soup = read_mesh(file.string()).soup;
  for (int i = 0; i < subdivisions; ++i) soup = subdivide_midpoint(soup);
  const Mesh mesh = Mesh::from_soup(soup);
  std::mt19937 rng(37);
  return make(name, mesh, limbs, radius, rng);
}

std::vector<Shape> elephant_cases() { return mesh_limb_cases("elephant", 3, 0.2); }

// The nonlinear model's result for an edit at order k, with the default options.
struct NonlinearRun {
  Quality quality;
  int iterations = 0;
  bool converged = false;
};

NonlinearRun run_nonlinear(Shape s, int order) {
  s.edit.settings.order = order;
  s.edit.deformation = Deformation::Nonlinear;
  const EditSolver solver(s.mesh, s.edit);
  VertexData<Vec3> p = s.mesh.positions();
  solver.evaluate(solver.transforms(s.edit), p);
  return {quality(s, p), solver.nonlinear_state()->iterations, solver.nonlinear_state()->converged};
}

// Totals over cases run at k = 2 and 3 against CGAL's ARAP (run here, 1,000 iterations): each
// case and order printed and handed to `check` (ours, the peer's).
struct Totals {
  int peer_folds = 0, peer_collapsed = 0, folds[2] = {0, 0}, collapsed[2] = {0, 0}, capped = 0;
};

template <class Check>
Totals against_arap(const std::vector<Shape>& cases, const Check& check) {
  Totals t;
  for (const Shape& s : cases) {
    const std::optional<PeerResult> arap = cgal_deform(s, 1000);
    EXPECT_TRUE(arap.has_value()) << s.name;
    if (!arap) continue;
    const Quality peer = quality(s, arap->positions);
    t.peer_folds += peer.folds;
    t.peer_collapsed += peer.collapsed;
    for (int k : {2, 3}) {
      const NonlinearRun run = run_nonlinear(s, k);
      t.folds[k - 2] += run.quality.folds;
      t.collapsed[k - 2] += run.quality.collapsed;
      t.capped += !run.converged;
      std::printf("%-28s k=%d folds %3d (ARAP %3d) collapsed %3d (ARAP %3d) iterations %d\n", s.name.c_str(), k,
                  run.quality.folds, peer.folds, run.quality.collapsed, peer.collapsed, run.iterations);
      check(s, k, run, peer);
    }
  }
  return t;
}

// At k = 2 and 3: every run converges, no case folds more than ARAP + 2 (the per-case
// rule) nor collapses more than ARAP + `collapsed_slack`, and in total fewer of both than ARAP.
void expect_near_arap(const std::vector<Shape>& cases, int collapsed_slack) {
  const Totals t = against_arap(cases, [&](const Shape& s, int k, const NonlinearRun& run, const Quality& peer) {
    EXPECT_TRUE(run.converged) << s.name << " k = " << k;
    EXPECT_LE(run.quality.folds, peer.folds + 2) << s.name << " k = " << k;
    EXPECT_LE(run.quality.collapsed, peer.collapsed + collapsed_slack) << s.name << " k = " << k;
  });
  for (int k : {0, 1}) {
    EXPECT_LE(t.folds[k], t.peer_folds) << "k = " << k + 2;
    EXPECT_LE(t.collapsed[k], t.peer_collapsed) << "k = " << k + 2;
  }
}

TEST(GallerySubset, ElephantLimbsAgainstArap) {
  const std::vector<Shape> cases = elephant_cases();
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_EQ(cases.size(), 8u);
  const Totals t = against_arap(cases, [](const Shape& s, int k, const NonlinearRun& run, const Quality& peer) {
    // Measured 2026-12-05 (evening): all converge; folds never more than ARAP's; collapsed
    // faces up to 14 against ARAP's 10 (the goal: ARAP's + 2).
    EXPECT_LE(run.quality.folds, peer.folds + 6) << s.name << " k = " << k;
    EXPECT_LE(run.quality.collapsed, 4 * peer.collapsed + 12) << s.name << " k = " << k;
  });
  // Not more folded edges than ARAP in total, within the 2 (the measured totals are in
  // docs/nonlinear.md, "Gallery").
  EXPECT_LE(t.folds[0], t.peer_folds + 2);
  EXPECT_LE(t.folds[1], t.peer_folds + 2);
  // Collapsed faces: at most ARAP's + 4 in total at each order (docs/nonlinear.md, "What the
  // gallery found", 21, 24 and 35). Measured 41 and 38 against ARAP's 49 (48 and 49 before the
  // stiffer compression of small supports); with the membrane's weight capped at 0.6 56 and 51,
  // with the two-sided membrane 65 and 64 (both fail this at k = 2).
  EXPECT_LE(t.collapsed[0], t.peer_collapsed + 4);
  EXPECT_LE(t.collapsed[1], t.peer_collapsed + 4);
  EXPECT_LE(t.capped, 1);
}

// Real files nobody tuned for (docs/nonlinear.md, "What the gallery found", 29): the limb edits
// of assimp-testmodels' spider and pig (both non-manifold, repaired as `convert --repair` does
// them; 16-534 free vertices), drawn with seed 37 per file, against CGAL's ARAP in the test.
TEST(GallerySubset, AssimpFilesAgainstArap) {
  const std::filesystem::path dir = "/usr/share/assimp/models/OBJ";
  if (!std::filesystem::is_directory(dir)) {
    if (data_required()) FAIL() << dir << " missing: apt-get install assimp-testmodels";
    GTEST_SKIP() << "assimp-testmodels not installed";
  }
  std::vector<Shape> cases;
  for (const char* file : {"spider.obj", "WusonOBJ.obj"}) {
    const Mesh mesh = Mesh::from_soup(read_mesh((dir / file).string()).soup, BuildOptions{.repair = true});
    std::mt19937 rng(37);
    for (Shape& s : limb_cases(file, mesh, 3, 0.2, rng)) cases.push_back(std::move(s));
  }
  ASSERT_GE(cases.size(), 12u);
  const Totals t = against_arap(cases, [](const Shape& s, int k, const NonlinearRun& run, const Quality& peer) {
    EXPECT_TRUE(run.converged) << s.name << " k = " << k;
    // The rule where ARAP is clean; elsewhere today's standing (measured 2026-12-05:
    // at most 8 folded edges more, the spider's two legs bent 137° at k = 3, 7 before the stiffer
    // compression of small supports, and 3 collapsed faces).
    EXPECT_LE(run.quality.folds, peer.folds == 0 ? 0 : peer.folds + 8) << s.name << " k = " << k;
    EXPECT_LE(run.quality.collapsed, peer.collapsed == 0 ? 0 : peer.collapsed + 3) << s.name << " k = " << k;
  });
  // In total no more folded edges than ARAP (+ 2) and at most half its collapsed faces: measured
  // 90 / 56 (k = 2) and 93 / 51 (k = 3) against ARAP's 111 / 133; 96 / 76 and 89 / 70 (which
  // fail it) with the constrained ring's membrane turned with its constraints' rotation, before
  // docs/nonlinear.md, "What the gallery found", 53.
  for (int k : {0, 1}) {
    EXPECT_LE(t.folds[k], t.peer_folds + 2) << "k = " << k + 2;
    EXPECT_LE(2 * t.collapsed[k], t.peer_collapsed) << "k = " << k + 2;
  }
}

// Small supports (the cow's limbs, 66-527 free vertices; drawn with seed 37 for this mesh alone,
// so the angles are not the gallery's): at k = 2 no case folds more than ARAP + 2, nor at all
// where ARAP does not. Before the heavier membrane on small supports (docs/nonlinear.md, "What
// the gallery found", 14) the leg twisted 137° here folded 9 edges where ARAP folds none (in the
// gallery, twisted 145°: 17).
TEST(GallerySubset, SmallSupportsFoldNoMoreThanArapAtOrder2) {
  const std::vector<Shape> cases = mesh_limb_cases("cow", 3, 0.2);
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_GE(cases.size(), 7u);
  for (const Shape& s : cases) {
    const std::optional<PeerResult> arap = cgal_deform(s, 1000);
    ASSERT_TRUE(arap.has_value()) << s.name;
    const Quality peer = quality(s, arap->positions);
    const NonlinearRun run = run_nonlinear(s, 2);
    std::printf("%-28s k=2 folds %3d (ARAP %3d) collapsed %3d (ARAP %3d) iterations %d\n", s.name.c_str(),
                run.quality.folds, peer.folds, run.quality.collapsed, peer.collapsed, run.iterations);
    EXPECT_LE(run.quality.folds, peer.folds == 0 ? 0 : peer.folds + 2) << s.name;
  }
}

// Handles moved without turning, as a translate gizmo moves them (drag_cases: each limb dragged
// sideways by 40-100 % of its length, the first also pushed toward the body by 20-40 %): the
// guidance field is the identity, so the model must find the rotations itself. Drawn with seed 37
// per mesh on the man and the elk (51-1,112 free vertices), against CGAL's ARAP in the test.
// Measured 2026-12-07: every run converges in 8-53 iterations; 1 / 1 folded edges and 5 / 2
// collapsed faces in all (k = 2 / 3) against ARAP's 4 / 6. Per case at most 1 folded edge more
// than ARAP (the man's leg dragged by 97 %, where ARAP folds none) and 3 collapsed faces (the
// man's leg pushed in by 22 % at k = 2, where ARAP collapses none; with the rest volume as the
// target it collapsed none, but the gallery's pushes folded 2-4 times as much as ARAP's:
// docs/nonlinear.md, "What the gallery found", 59).
TEST(GallerySubset, TranslatedHandlesAgainstArap) {
  std::vector<Shape> cases;
  for (const char* name : {"man", "elk"})
    for (Shape& s : mesh_limb_cases(name, 3, name == std::string("man") ? 0.18 : 0.2, 0, drag_cases))
      cases.push_back(std::move(s));
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_EQ(cases.size(), 8u);
  expect_near_arap(cases, 3);
}

// Handles turned in place about their centres, as a rotate gizmo turns them (turn_cases: each
// limb's handle turned 45-120 degrees so that its end swings away from the body; the limb bends
// one way at its root and back below the handle), on the cow and the elk (51-527 free
// vertices), against CGAL's ARAP in the test. Measured 2026-12-07: 23 / 18 folded edges /
// collapsed faces in all at k = 2 against ARAP's 32 / 25; per case at most as many folds as
// ARAP, and up to 4 collapsed faces more (the cow's tail turned 116 degrees: 11 against 7).
TEST(GallerySubset, HandlesTurnedInPlaceAgainstArap) {
  std::vector<Shape> cases;
  for (const char* name : {"cow", "elk"})
    for (Shape& s : mesh_limb_cases(name, 3, 0.2, 0, turn_cases)) cases.push_back(std::move(s));
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_EQ(cases.size(), 6u);
  expect_near_arap(cases, 4);
}

// Handles grown about their centres, as a scale gizmo grows them (scale_cases' grows: each limb's end 1.6-2 times
// its size), on the cow, the camel and the hand, against CGAL's ARAP in the test. A handle grown about its centre
// shortens the band between it and the fixed rim; until that band took the growth the geometry leaves it rather than
// having it forced (docs/nonlinear.md, "What the gallery found", 64), it buckled there: 38 and 38 folded edges, 33
// and 34 collapsed faces in all at k = 2 and 3, against ARAP's 17 and 16 (the cow's tail tuft grown 1.97: 22 and 23
// folded edges where ARAP folds none). Measured since: 1 and 6 folded edges, 6 and 10 collapsed faces; the tuft at
// k = 3 still folds 6 edges and collapses 10 faces (ARAP 0 and 1). Shrunk handles are not in it: their model did not
// change, and the cow's tuft shrunk to 0.53 collapses 19 and 36 faces against ARAP's 8.
TEST(GallerySubset, GrownHandlesAgainstArap) {
  std::vector<Shape> cases;
  for (const char* name : {"cow", "camel", "hand"})
    for (Shape& s : mesh_limb_cases(name, 3, 0.2, 0, scale_cases))
      if (s.name.find("grow") != std::string::npos) cases.push_back(std::move(s));
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_EQ(cases.size(), 9u);
  const Totals t = against_arap(cases, [](const Shape& s, int k, const NonlinearRun& run, const Quality& peer) {
    EXPECT_TRUE(run.converged) << s.name << " k = " << k;
    EXPECT_LE(run.quality.folds, peer.folds + 6) << s.name << " k = " << k;
    EXPECT_LE(run.quality.collapsed, peer.collapsed + 10) << s.name << " k = " << k;
  });
  for (int k : {0, 1}) {
    EXPECT_LE(2 * t.folds[k], t.peer_folds) << "k = " << k + 2;
    EXPECT_LE(t.collapsed[k], t.peer_collapsed) << "k = " << k + 2;
  }
}

// A scaled handle's volume target (docs/nonlinear.md, "Volume"): the bunny's ear (the gallery's
// first limb, 0.2 of the diagonal) with its end scaled about its centre, k = 2. The volume
// changes with the scale's sign and by less than the whole limb scaled so would change it:
// |V - V rest| < |s^3 - 1| V limb, V limb the support's volume closed at its rim. Until
// 2026-12-07 (docs/nonlinear.md, "What the gallery found", 60) the target was the rest volume
// times the mean cube of the scale over all the mesh's vertices, as if each vertex held an even
// share of the volume: the thin ear grown 1.8 times gained 19 % of the whole bunny's volume, 3.4
// times its bound (now 0.27 of it); shrunk to 0.6 it lost 0.21 of its bound (now 0.35).
TEST(GallerySubset, ScaledHandleChangesTheVolumeByNoMoreThanItsLimb) {
  const std::filesystem::path file = cgal_mesh_dir().empty() ? "" : cgal_mesh_dir() / "bunny00.off";
  if (file.empty() || !std::filesystem::exists(file)) {
    if (data_required()) ADD_FAILURE() << "bunny00.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  const Mesh mesh = Mesh::from_soup(read_mesh(file.string()).soup);
  const std::vector<Limb> limbs = limbs_of(mesh, 2, 0.2);
  ASSERT_FALSE(limbs.empty());
  const Limb& ear = limbs[0];
  // The volume of the faces with every corner in `only` (sorted; all faces without), coned to the rim.
  const auto volume = [&](const VertexData<Vec3>& p, const std::vector<Vertex>* only) {
    const auto in = [&](Vertex x) { return !only || std::binary_search(only->begin(), only->end(), x); };
    double v = 0.0;
    for (Face f : mesh.faces()) {
      const auto [a, b, c] = mesh.vertices(f);
      if (!(in(a) && in(b) && in(c))) continue;
      v += (p[a] - ear.rim).dot((p[b] - ear.rim).cross(p[c] - ear.rim)) / 6.0;
    }
    return v;
  };
  const double rest = volume(mesh.positions(), nullptr), limb = volume(mesh.positions(), &ear.support);
  for (const double scale : {0.6, 1.8}) {
    Shape s = limb_case("bunny00-ear", mesh, {&ear}, {limb_transform(mesh, ear, LimbEdit::Scale, scale)});
    s.edit.settings.order = 2;
    s.edit.deformation = Deformation::Nonlinear;
    const EditSolver solver(s.mesh, s.edit);
    VertexData<Vec3> p = s.mesh.positions();
    solver.evaluate(solver.transforms(s.edit), p);
    const double change = volume(p, nullptr) - rest, bound = (scale * scale * scale - 1.0) * limb;
    std::printf("ear scaled %.1f: volume change %.5f, the limb's bound %.5f (of %.5f)\n", scale, change, bound, rest);
    EXPECT_TRUE(solver.nonlinear_state()->converged) << "scale " << scale;
    EXPECT_GT(change / bound, 0.0) << "scale " << scale;
    EXPECT_LT(change / bound, 1.0) << "scale " << scale;
  }
}

// The volume target of a dragged handle (docs/nonlinear.md, "Volume"): the survey's capsule
// (radius 1, length 8) with its top pushed 1.5 toward the fixed bottom, k = 2. The push removes
// what a tube shortened by 1.5 loses, 1.5 pi of (8 + 4/3) pi: 0.839 of the volume stays (with
// the rest volume as the target the capsule kept it all, swelling); the target is the
// same in any coordinates (the mesh moved far from the origin gives the same shape, moved);
// and a turn of 1e-4 rad about the handle's centre added to the push changes the shape by
// little (the drag is continuous where the turn vanishes).
TEST(GallerySubset, DraggedHandlesSetTheVolumeTargetAlike) {
  const Shape base = cylinder_bend();
  const auto deformed = [](Shape s, const Eigen::Affine3d& t, const Vec3& offset) {
    TriangleSoup soup = s.mesh.to_soup();
    for (Vec3& v : soup.positions) v += offset;
    s.mesh = Mesh::from_soup(soup);
    s.edit.settings.order = 2;
    s.edit.deformation = Deformation::Nonlinear;
    s.edit.handles[0].matrix = Eigen::Translation3d(offset) * t * Eigen::Translation3d(-offset);
    const EditSolver solver(s.mesh, s.edit);
    VertexData<Vec3> p = s.mesh.positions();
    solver.evaluate(solver.transforms(s.edit), p);
    EXPECT_TRUE(solver.nonlinear_state()->converged);
    for (Vec3& v : p) v -= offset;
    return p;
  };
  const auto volume = [&](const VertexData<Vec3>& p) {
    double v = 0.0;
    for (Face f : base.mesh.faces()) {
      const auto h = base.mesh.halfedges(f);
      v += p[base.mesh.to_vertex(h[0])].dot(p[base.mesh.to_vertex(h[1])].cross(p[base.mesh.to_vertex(h[2])])) / 6.0;
    }
    return v;
  };
  Vec3 centre = Vec3::Zero();
  for (Vertex v : base.edit.handles[0].vertices)
    centre += base.mesh.position(v) / double(base.edit.handles[0].vertices.size());
  const Eigen::Affine3d push(Eigen::Translation3d(Vec3(0.0, 0.0, -1.5)));
  const VertexData<Vec3> pushed = deformed(base, push, Vec3::Zero());
  EXPECT_NEAR(volume(pushed) / volume(base.mesh.positions()), 1.0 - 1.5 / (8.0 + 4.0 / 3.0), 0.01);
  const Eigen::Affine3d turned =
      push * Eigen::Translation3d(centre) * Eigen::AngleAxisd(1e-4, Vec3::UnitX()) * Eigen::Translation3d(-centre);
  const VertexData<Vec3> nearly = deformed(base, turned, Vec3::Zero());
  const VertexData<Vec3> far = deformed(base, turned, Vec3(1000.0, -500.0, 300.0));
  double moved = 0.0, turn = 0.0;
  for (Vertex v : base.mesh.vertices()) {
    moved = std::max(moved, (far[v] - nearly[v]).norm());
    turn = std::max(turn, (nearly[v] - pushed[v]).norm());
  }
  std::printf("volume %.4f of the rest; far from the origin %.2e; turned %.2e\n",
              volume(pushed) / volume(base.mesh.positions()), moved, turn);
  EXPECT_LT(moved, 1e-5);  // the capsule is 10 long; the solve's tolerance is 1e-4 of it
  EXPECT_LT(turn, 1e-2);
}

// Order 1 with the 1-ring fit and no volume term is ARAP's own alternation on BCM's boundary;
// with the spokes-and-rims cell, its right-hand side and the mean rotation on the edges to
// the constraints (face_fans.h) it folds and collapses like CGAL's ARAP on the same edits,
// run in the test. Measured here: 44 folded edges and 59 collapsed faces against 46 and 49,
// per case at most 2 folded edges and 3 collapsed faces more. (On the gallery's own elephant
// edits, 36 / 49 against 40 / 41; with the spokes and the row's own rotation at the constraints,
// until 2026-12-02, 55 / 61, and 13 folded edges against 7 on one twist.)
TEST(GallerySubset, OrderOneWithTheOneRingFitIsArap) {
  const std::vector<Shape> cases = elephant_cases();
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  Quality ours, peers;
  for (Shape s : cases) {
    const std::optional<PeerResult> arap = cgal_deform(s, 1000);
    ASSERT_TRUE(arap.has_value()) << s.name;
    const Quality peer = quality(s, arap->positions);
    s.edit.settings.order = 1;
    s.edit.multiresolution = false;
    s.edit.deformation = Deformation::Nonlinear;
    s.edit.nonlinear.rotation_smoothing = 0;
    s.edit.nonlinear.preserve_volume = false;
    s.edit.nonlinear.max_iterations = 1000;
    const EditSolver solver(s.mesh, s.edit);
    VertexData<Vec3> p = s.mesh.positions();
    solver.evaluate(solver.transforms(s.edit), p);
    const Quality q = quality(s, p);
    std::printf("%-28s k=1 folds %3d (ARAP %3d) collapsed %3d (ARAP %3d) iterations %d\n", s.name.c_str(), q.folds,
                peer.folds, q.collapsed, peer.collapsed, solver.nonlinear_state()->iterations);
    EXPECT_TRUE(solver.nonlinear_state()->converged) << s.name;
    EXPECT_LE(q.folds, peer.folds + 3) << s.name;
    EXPECT_LE(q.collapsed, peer.collapsed + 5) << s.name;
    ours.folds += q.folds, ours.collapsed += q.collapsed;
    peers.folds += peer.folds, peers.collapsed += peer.collapsed;
  }
  EXPECT_LE(ours.folds, peers.folds + 2);
  EXPECT_LE(ours.collapsed, peers.collapsed * 4 / 3);
}

// A solve that reaches its cap ends on the best image it made, not on the last iterate
// (docs/nonlinear.md, "What the gallery found": the capped runs cycle, and their last iterate
// can be the worst point of the cycle). Capped after 5, 10, 15 and 20 iterations, each of the
// elephant's edits then reports a step that never grows with the cap: each solve repeats the
// shorter one's iterations and keeps the best of more of them.
TEST(GallerySubset, CappedSolvesEndOnTheirBestIterate) {
  const std::vector<Shape> cases = elephant_cases();
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  int capped = 0;
  for (const Shape& base : cases)
    for (int k : {2, 3}) {
      double previous = std::numeric_limits<double>::infinity();
      for (int cap : {5, 10, 15, 20}) {
        Shape s = base;
        s.edit.settings.order = k;
        s.edit.deformation = Deformation::Nonlinear;
        s.edit.nonlinear.max_iterations = cap;
        const EditSolver solver(s.mesh, s.edit);
        VertexData<Vec3> p = s.mesh.positions();
        solver.evaluate(solver.transforms(s.edit), p);
        const NonlinearState& state = *solver.nonlinear_state();
        if (state.converged) break;
        ++capped;
        EXPECT_LE(state.step, previous) << s.name << " k = " << k << ", cap " << cap;
        EXPECT_EQ(solver.problems(p).non_finite, 0) << s.name;
        previous = state.step;
      }
    }
  EXPECT_GE(capped, 8);  // the check has capped runs to look at
}

// The gallery's first pulls (a limb stretched by 30 %) of the armadillo and the bunny at k = 3:
// before the membrane term (NonlinearOptions::membrane) the volume term's k = 3 response thinned
// each limb in a band (12 folded edges and 78 collapsed faces each); k = 2 and the other pulls
// were clean. The cases are drawn as bench_gallery draws them (seed 37, armadillo then bunny).
TEST(GallerySubset, PullsAtOrder3StayClean) {
  const std::filesystem::path dir = cgal_mesh_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "armadillo.off") || !std::filesystem::exists(dir / "bunny00.off")) {
    if (data_required()) FAIL() << "armadillo.off or bunny00.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  std::mt19937 rng(37);
  std::vector<Shape> pulls;
  for (auto [name, limbs, radius] : {std::tuple{"armadillo", 3, 0.18}, std::tuple{"bunny00", 2, 0.2}}) {
    const Mesh mesh = Mesh::from_soup(read_mesh((dir / (std::string(name) + ".off")).string()).soup);
    for (Shape& s : limb_cases(name, mesh, limbs, radius, rng))
      if (s.name.ends_with("pull30")) pulls.push_back(std::move(s));
  }
  ASSERT_EQ(pulls.size(), 2u);
  for (const Shape& s : pulls) {
    const NonlinearRun run = run_nonlinear(s, 3);
    std::printf("%-28s k=3 folds %3d collapsed %3d iterations %d\n", s.name.c_str(), run.quality.folds,
                run.quality.collapsed, run.iterations);
    EXPECT_TRUE(run.converged) << s.name;
    EXPECT_EQ(run.quality.folds, 0) << s.name;
    EXPECT_EQ(run.quality.collapsed, 0) << s.name;
  }
}

// Homer's limbs (drawn with seed 37 for this mesh alone; supports of a few hundred free
// vertices, where the membrane weighs most): bends and twists keep their cross-sections
// (docs/nonlinear.md, "What the gallery found", 35, 51 and 54): at most four fifths of ARAP's
// folded edges and of its collapsed faces. Measured 2026-12-07: folded edges 99 / 114 (k = 2 /
// 3) against ARAP's 160, collapsed faces 81 / 110 against 152; with the push of item 54 at 1
// instead of 1.25, 106 / 113 and 85 / 125, which fails the collapse at k = 3. Before the
// membrane turned with the field where its 1-ring fit is ill-conditioned 146 / 159 and 129 /
// 114; before the stiffer compression of small supports 146 / 172 and 153 / 157.
TEST(GallerySubset, SmallLimbsKeepTheirCrossSections) {
  const std::vector<Shape> cases = mesh_limb_cases("homer", 3, 0.2);
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_GE(cases.size(), 7u);
  const Totals t = against_arap(cases, [](const Shape&, int, const NonlinearRun&, const Quality&) {});
  for (int k : {0, 1}) {
    EXPECT_LE(5 * t.folds[k], 4 * t.peer_folds) << "k = " << k + 2;
    EXPECT_LE(5 * t.collapsed[k], 4 * t.peer_collapsed) << "k = " << k + 2;
  }
}

// Supports of 8,000-10,000 free vertices (the armadillo subdivided once, its two limbs at 0.3 of
// the diagonal as in the gallery; drawn with seed 37 for this mesh alone). With the membrane
// turned by its own 1-ring rotations alone, under half of the compression's push, the twists
// iterated slowly and folded; turned halfway to the smoothed field with the push of small
// supports they converge sooner and cleaner (docs/nonlinear.md, "What the gallery found", 56).
// Measured 2026-12-07: no folded edge or collapsed face in 39-55 iterations; before, 9 / 20, 7 /
// 18 and 7 / 13 folded edges / collapsed faces in three of the four runs, 75-258 iterations.
TEST(GallerySubset, LargeLimbTwistsConvergeCleanly) {
  std::vector<Shape> twists;
  for (Shape& s : mesh_limb_cases("armadillo", 2, 0.3, 1))
    if (s.name.find("twist") != std::string::npos) twists.push_back(std::move(s));
  if (twists.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_EQ(twists.size(), 2u);
  for (const Shape& s : twists)
    for (int k : {2, 3}) {
      const NonlinearRun run = run_nonlinear(s, k);
      std::printf("%-28s k=%d support %zu folds %3d collapsed %3d iterations %d\n", s.name.c_str(), k,
                  s.edit.support.size(), run.quality.folds, run.quality.collapsed, run.iterations);
      EXPECT_TRUE(run.converged) << s.name << " k = " << k;
      EXPECT_LE(run.iterations, 80) << s.name << " k = " << k;
      EXPECT_EQ(run.quality.folds, 0) << s.name << " k = " << k;
      EXPECT_EQ(run.quality.collapsed, 0) << s.name << " k = " << k;
    }
}

// libcgal-demo's half-cylinder sheet, its limb tips at corners (1,600 free vertices, handles of
// about ten): the membrane's 1-ring rotations of its corner fans swung and 3 of the 8 edits at
// k = 2 reached the cap (steps of 2-9 % of the extent). Turned with the field where their fit
// is ill-conditioned, every run converges (docs/nonlinear.md, "What the gallery found", 50 and 51).
TEST(GallerySubset, CornersOfASheetConverge) {
  const std::vector<Shape> cases = mesh_limb_cases("cylinder_locally_refined", 3, 0.2);
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  ASSERT_GE(cases.size(), 7u);
  for (const Shape& s : cases)
    for (int k : {2, 3}) {
      const NonlinearRun run = run_nonlinear(s, k);
      std::printf("%-28s k=%d folds %3d collapsed %3d iterations %d\n", s.name.c_str(), k, run.quality.folds,
                  run.quality.collapsed, run.iterations);
      EXPECT_TRUE(run.converged) << s.name << ", k = " << k;
    }
}

// Meshes with holes (libcgal-demo's holes and mask_cone; drawn with seed 37 for each mesh alone).
// Where a support reaches a hole of a curved mesh, the decomposition's smooth base curls away
// from the surface there (multires/operator_shape.h, the lifted boundary) and the detail it
// invents folds under large rotations, so the nonlinear model carries the detail: with
// multiresolution on it folds no more than off (the bound: 2 folded edges). What the
// decomposition does with the same edits is measured alongside. Measured 2026-12-06: 14 such
// edits, 58 folded edges carried by the model, 116 decomposed (holes' limb bent 128 degrees: 7
// against 41).
TEST(GallerySubset, OpenBoundariesFoldNoMoreWithMultiresolution) {
  std::vector<Shape> cases = mesh_limb_cases("holes", 3, 0.2), cone = mesh_limb_cases("mask_cone", 3, 0.2);
  cases.insert(cases.end(), cone.begin(), cone.end());
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  int lifted = 0, model_folds = 0, decomposed_folds = 0;
  for (Shape s : cases) {
    s.edit.settings.order = 2;
    s.edit.deformation = Deformation::Nonlinear;
    const EditSolver on(s.mesh, s.edit);
    VertexData<Vec3> p = s.mesh.positions();
    on.evaluate(on.transforms(s.edit), p);
    const int folds_on = quality(s, p).folds;
    s.edit.multiresolution = false;
    const NonlinearRun off = run_nonlinear(s, 2);
    EXPECT_LE(folds_on, off.quality.folds + 2) << s.name;
    const Regions regions = edit_regions(s.mesh, s.edit);
    const OperatorShape shape = base_operator_shape(s.mesh, regions, s.edit.settings);
    if (shape.overhanging > 0 || shape.lifted_boundary == 0) continue;
    ++lifted;
    EXPECT_TRUE(on.stats().multires && on.stats().multires->detail_by_model) << s.name;
    MultiresOptions options;
    options.model = nonlinear_base_model(s.edit.nonlinear);
    const MultiresSolver decomposed(s.mesh, regions, s.edit.settings, options);
    VertexData<Vec3> d = s.mesh.positions();
    decomposed.evaluate(on.transforms(s.edit), d);
    const int folds_decomposed = quality(s, d).folds;
    model_folds += folds_on;
    decomposed_folds += folds_decomposed;
    std::printf("%-28s folded edges: carried by the model %3d, without multiresolution %3d, decomposed %3d\n",
                s.name.c_str(), folds_on, off.quality.folds, folds_decomposed);
  }
  EXPECT_GE(lifted, 10);
  EXPECT_GT(2 * decomposed_folds, 3 * model_folds);
}

// Where the decomposition holds the detail (it does not overhang its base) the nonlinear model bends
// the smooth base and re-adds the detail. Where the base bends tighter than the detail is tall (a
// limb of the bear turned in place or twisted, blobby's lobes bent) the detail re-added flips or
// is flattened and edges fold that the model on the detailed mesh leaves flat; every libcgal-demo
// file's five families had 37 / 28 edits (k = 2 / 3) folding more than 2 edges more with
// multiresolution than without it (docs/nonlinear.md, "What the gallery found", 65). EditSolver
// then solves the frame on the detailed mesh as well and keeps the result with fewer folds.
TEST(GallerySubset, DetailTheDecompositionFoldsIsCarriedByTheModel) {
  std::vector<Shape> cases;
  for (const char* name : {"bear_bis", "blobby", "knot1"})
    for (CaseMaker make : {limb_cases, turn_cases})
      for (Shape& s : mesh_limb_cases(name, 3, 0.2, 0, make)) cases.push_back(std::move(s));
  if (cases.empty()) GTEST_SKIP() << "libcgal-demo meshes not found";
  int decomposed_runs = 0, carried = 0, decomposed_folds = 0, kept_folds = 0;
  for (Shape s : cases)
    for (int k : {2, 3}) {
      s.edit.settings.order = k;
      s.edit.deformation = Deformation::Nonlinear;
      s.edit.multiresolution = true;
      const EditSolver on(s.mesh, s.edit);
      VertexData<Vec3> p = s.mesh.positions();
      on.evaluate(on.transforms(s.edit), p);
      const int folds_on = quality(s, p).folds;
      s.edit.multiresolution = false;
      const int folds_off = run_nonlinear(s, k).quality.folds;
      EXPECT_LE(folds_on, folds_off + 2) << s.name << " k = " << k;
      if (!on.stats().multires || on.stats().multires->detail_by_model) continue;
      ++decomposed_runs;
      carried += !on.detail_carried().empty();
      MultiresOptions options;
      options.model = nonlinear_base_model(s.edit.nonlinear);
      const MultiresSolver decomposed(s.mesh, on.regions(), s.edit.settings, options);
      VertexData<Vec3> d = s.mesh.positions();
      decomposed.evaluate(on.transforms(s.edit), d);
      const int folds_decomposed = quality(s, d).folds;
      EXPECT_LE(folds_on, folds_decomposed) << s.name << " k = " << k;
      decomposed_folds += folds_decomposed;
      kept_folds += folds_on;
      std::printf("%-34s k=%d folded edges: decomposed %3d, kept %3d (%s), without multiresolution %3d\n",
                  s.name.c_str(), k, folds_decomposed, folds_on, on.detail_carried().empty() ? "decomposed" : "carried",
                  folds_off);
    }
  std::printf("decomposed runs %d, carried %d, folded edges %d -> %d\n", decomposed_runs, carried, decomposed_folds,
              kept_folds);
  EXPECT_GE(carried, 1);
  EXPECT_LT(kept_folds, decomposed_folds);
}

}  // namespace
