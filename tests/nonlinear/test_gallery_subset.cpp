// A subset of the gallery (bench/bench_gallery.cpp, docs/nonlinear.md "Gallery"): the seeded limb
// edits of libcgal-demo's elephant (bends, twists, a pull and two limbs at once; 186-513 free
// vertices), the nonlinear model at k = 2 and 3 against CGAL's ARAP run in the same test.
// These bounds guard today's standing against the peer; they are not the goal (no more
// collapsed faces than ARAP), which the model does not meet yet.
#include "cgal_arap.h"
#include "gallery_cases.h"
#include "test_support.h"

#include "freeform/edit/edit_solver.h"
#include "freeform/mesh/folds.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

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

TEST(GallerySubset, ElephantLimbsAgainstArap) {
  const std::filesystem::path file = cgal_mesh_dir().empty() ? "" : cgal_mesh_dir() / "elephant.off";
  if (file.empty() || !std::filesystem::exists(file)) {
    if (data_required()) FAIL() << "elephant.off missing: run scripts/fetch-data.sh";
    GTEST_SKIP() << "libcgal-demo meshes not found";
  }
  const Mesh mesh = Mesh::from_soup(read_mesh(file.string()).soup);
  std::mt19937 rng(37);
  const std::vector<Shape> cases = limb_cases("elephant", mesh, 3, 0.2, rng);
  ASSERT_EQ(cases.size(), 8u);
  int peer_folds = 0, folds[2] = {0, 0};
  for (const Shape& base : cases) {
    const std::optional<PeerResult> arap = cgal_deform(base, 1000);
    ASSERT_TRUE(arap.has_value()) << base.name;
    const Quality peer = quality(base, arap->positions);
    peer_folds += peer.folds;
    for (int k : {2, 3}) {
      Shape s = base;
      s.edit.settings.order = k;
      s.edit.deformation = Deformation::Nonlinear;
      const EditSolver solver(s.mesh, s.edit);
      VertexData<Vec3> p = s.mesh.positions();
      solver.evaluate(solver.transforms(s.edit), p);
      const Quality q = quality(s, p);
      folds[k - 2] += q.folds;
      std::printf("%-28s k=%d folds %3d (ARAP %3d) collapsed %3d (ARAP %3d) iterations %d\n", s.name.c_str(), k, q.folds,
                  peer.folds, q.collapsed, peer.collapsed, solver.nonlinear_state()->iterations);
      EXPECT_TRUE(solver.nonlinear_state()->converged) << s.name << " k = " << k;
      // Measured 2026-11-28 (the narrower rotation fit): folds at most ARAP's + 5; collapsed
      // faces up to 48 against ARAP's 19 and 7 against 0 (the goal: ARAP's + 2).
      EXPECT_LE(q.folds, peer.folds + 6) << s.name << " k = " << k;
      EXPECT_LE(q.collapsed, 4 * peer.collapsed + 12) << s.name << " k = " << k;
    }
  }
  // Not more folded edges than ARAP in total, within the 2 (measured 41 and 47 against
  // 46; with the wider fit before 2026-11-28: 35 and 43, and about 60 % more collapsed faces
  // over the whole gallery).
  EXPECT_LE(folds[0], peer_folds + 2);
  EXPECT_LE(folds[1], peer_folds + 2);
}

}  // namespace
