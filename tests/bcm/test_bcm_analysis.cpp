// bcm_analysis.h: the pattern predicted from the connectivity is exactly the assembled A_pp's
// lower triangle (irregular meshes, right angles, supports on the mesh boundary, k = 1..3,
// lambda = 0); the solver uses the analysis run ahead and gives the same result as with its
// own, and it falls back to its own when handed an analysis of another pattern. Dropped
// without get() (a cancel), it returns without waiting for the ordering.
#include "bcm_fixtures.h"

#include "freeform/bcm/bcm_analysis.h"
#include "freeform/bcm/bcm_system.h"
#include "freeform/common/held_threads.h"
#include "freeform/common/parallel.h"

#include <chrono>
#include <future>
#include <memory>
#include <string>
#include <thread>
#include <vector>

namespace freeform::test {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

void expect_same_pattern(const SpMat& want, const SpMat& got) {
  ASSERT_EQ(want.rows(), got.rows());
  ASSERT_EQ(want.cols(), got.cols());
  ASSERT_EQ(want.nonZeros(), got.nonZeros());
  for (Eigen::Index j = 0; j <= want.cols(); ++j) ASSERT_EQ(want.outerIndexPtr()[j], got.outerIndexPtr()[j]) << j;
  for (Eigen::Index t = 0; t < want.nonZeros(); ++t) ASSERT_EQ(want.innerIndexPtr()[t], got.innerIndexPtr()[t]) << t;
}

TEST(BcmAnalysis, PatternIsTheAssembledLowerTriangle) {
  const BumpyScene bumpy;
  const PlanarDisk disk;  // jittered, irregular valences
  const Mesh sphere = Mesh::from_soup(make_icosphere(3));
  std::vector<Vertex> cap, cap_handle;
  for (Vertex v : sphere.vertices()) {
    if (sphere.position(v).z() > -0.3) cap.push_back(v);
    if (sphere.position(v).z() > 0.9) cap_handle.push_back(v);
  }
  const Mesh plane = Mesh::from_soup(make_plane(12, 12));
  std::vector<Vertex> left;  // free vertices on the mesh boundary
  for (Vertex v : plane.vertices())
    if (plane.position(v).x() < 0.6) left.push_back(v);
  struct Case {
    const Mesh& mesh;
    Regions regions;
  };
  const Case cases[] = {
      {bumpy.mesh, bumpy.regions()},
      {disk.mesh, Regions(disk.mesh, disk.rings(0, 8), {{disk.rings(0, 1), true}})},
      {sphere, Regions(sphere, cap, {{cap_handle, true}})},
      {plane, Regions(plane, left, {{within(plane, Vec3(0.2, 0.5, 0), 0.1), true}})},
  };
  for (const Case& c : cases)
    for (int k = 1; k <= 3; ++k)
      for (double outer : {Smoothness::kDefault, 0.0}) {  // c = 0: lambda = 0 on the fixed ring
        BcmSettings s;
        s.order = k;
        s.smoothness.outer = outer;
        const SpMat a = assemble_bcm_system(c.mesh, c.mesh.positions(), c.regions, s).a_pp;
        const SpMat lower = a.triangularView<Eigen::Lower>();
        SCOPED_TRACE("case " + std::to_string(&c - cases) + ", k = " + std::to_string(k) + ", outer " +
                     std::to_string(outer));
        expect_same_pattern(lower, bcm_lower_pattern(c.mesh, c.regions, k));
      }
}

// A 150 x 150 plane held at its border: 22k free vertices (kSmall), below BcmAnalysis::kMinFree
// to keep the test quick: the analyses here are started with that lower threshold.
constexpr int kSmall = 20000;
struct LargePlane {
  Mesh mesh = Mesh::from_soup(make_bumpy_plane(150, 150, 0.05, 2.0));
  std::vector<Vertex> inside(double margin) const {
    std::vector<Vertex> out;
    for (Vertex v : mesh.vertices()) {
      const Vec3 p = mesh.position(v);
      if (p.x() > margin && p.x() < 1 - margin && p.y() > margin && p.y() < 1 - margin) out.push_back(v);
    }
    return out;
  }
  Regions regions(double margin) const {
    return Regions(mesh, inside(margin), {{within(mesh, Vec3(0.5, 0.5, 0), 0.04), true}});
  }
};

TEST(BcmAnalysis, SolverUsesItAndFallsBackForAnotherPattern) {
  if (thread_budget() < 2) GTEST_SKIP() << "FREEFORM_THREADS=1: no analysis ahead";
  const LargePlane p;
  const Regions regions = p.regions(0.001);
  ASSERT_GE(regions.n_free(), kSmall);
  BcmSettings s;
  s.order = 2;
  BcmAnalysis mine(p.mesh, regions, s, kSmall);
  const BcmSolver ahead(p.mesh, regions, s, {}, nullptr, false, RowOrder::BreadthFirst, &mine);
  EXPECT_TRUE(ahead.stats().analysis_ahead);
  EXPECT_GT(ahead.stats().analysis_ahead_ms, 0.0);

  // An analysis of a smaller support (another pattern, still large enough to be started).
  const Regions other = p.regions(0.02);
  BcmAnalysis wrong(p.mesh, other, s, kSmall);
  ASSERT_TRUE(wrong.started());
  const BcmSolver own(p.mesh, regions, s, {}, nullptr, false, RowOrder::BreadthFirst, &wrong);
  EXPECT_FALSE(own.stats().analysis_ahead);

  const Eigen::Affine3d t(Eigen::Translation3d(0.0, 0.0, 0.2) * Eigen::AngleAxisd(0.4, Vec3::UnitX()));
  RowMatrix x1(ahead.n_free(), 3), x2(own.n_free(), 3);
  ahead.evaluate(std::span(&t, 1), x1);
  own.evaluate(std::span(&t, 1), x2);
  EXPECT_LT((x1 - x2).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT(x1.col(2).maxCoeff() - x1.col(2).minCoeff(), 0.15);  // lifted: the rest bumps span 0.1
}

// A dropped analysis lets its thread go just after its destructor returns (the thread stops
// at its next check): wait for that before starting the next one.
void wait_for_released_threads() {
  for (int i = 0; i < 1000 && threads_free() < thread_budget(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
}

TEST(BcmAnalysis, StartsOnlyForLargeSymmetricCholeskySystems) {
  if (thread_budget() < 2) GTEST_SKIP() << "FREEFORM_THREADS=1: no analysis ahead";
  const LargePlane p;
  const Regions large = p.regions(0.001);
  const BumpyScene bumpy;
  const Regions small = bumpy.regions();
  BcmSettings s;
  s.order = 3;
  EXPECT_TRUE(BcmAnalysis(p.mesh, large, s, kSmall).started());
  wait_for_released_threads();
  EXPECT_FALSE(BcmAnalysis(bumpy.mesh, small, s).started());
  EXPECT_FALSE(BcmAnalysis(p.mesh, large, s).started());  // 22k free: below kMinFree
  s.smoothness.outer = 0.0;  // lambda_1 = lambda_2 = 0: still symmetric
  EXPECT_TRUE(BcmAnalysis(p.mesh, large, s, kSmall).started());
  wait_for_released_threads();
  s.smoothness.outer = 1.0;  // k = 3, c = 1: unsymmetric (LU)
  EXPECT_FALSE(BcmAnalysis(p.mesh, large, s, kSmall).started());
  s.smoothness.outer = Smoothness::kDefault;
  s.solver = SolverKind::Umfpack;
  EXPECT_FALSE(BcmAnalysis(p.mesh, large, s, kSmall).started());
}

// Analyses ahead side by side never take more threads than the cores beside the caller's: on 2
// cores the operator shape's fill, started beside the system's analysis, analyzes its A itself.
// Each started one holds its thread from its constructor on.
TEST(BcmAnalysis, NeverMoreAnalysesAheadThanCoresBesideTheCaller) {
  if (thread_budget() < 2) GTEST_SKIP() << "FREEFORM_THREADS=1: no analysis ahead";
  const LargePlane p;
  const Regions regions = p.regions(0.001);
  BcmSettings s;
  s.order = 2;
  std::promise<void> release;
  const std::shared_future<void> go = release.get_future().share();
  std::vector<std::unique_ptr<BcmAnalysis>> ahead;
  for (int i = 0; i <= thread_budget(); ++i)
    ahead.push_back(std::make_unique<BcmAnalysis>(p.mesh, regions, s, kSmall, [go] { go.wait(); }));
  int started = 0;
  for (const auto& a : ahead) started += a->started() ? 1 : 0;
  EXPECT_EQ(started, thread_budget() - 1);
  EXPECT_EQ(threads_free(), 1);
  release.set_value();
  for (const auto& a : ahead)
    if (a->started()) {
      EXPECT_NE(a->get(), nullptr);
    }
  EXPECT_EQ(threads_free(), thread_budget());
}

// The columns walked in blocks on several threads give the matrix walked in one block (the
// budget held elsewhere), values 0.
TEST(BcmAnalysis, PatternIsTheSameWalkedInBlocks) {
  if (thread_budget() < 2) GTEST_SKIP() << "FREEFORM_THREADS=1: one block";
  const LargePlane p;
  const Regions regions = p.regions(0.001);
  for (int k = 1; k <= 3; ++k) {
    SCOPED_TRACE("k = " + std::to_string(k));
    const SpMat in_blocks = bcm_lower_pattern(p.mesh, regions, k);
    std::vector<std::unique_ptr<HeldThread>> held;
    for (int i = 1; i < thread_budget(); ++i) held.push_back(std::make_unique<HeldThread>());
    const SpMat in_one = bcm_lower_pattern(p.mesh, regions, k);
    expect_same_pattern(in_one, in_blocks);
    for (Eigen::Index t = 0; t < in_blocks.nonZeros(); ++t) ASSERT_EQ(in_blocks.valuePtr()[t], 0.0) << t;
  }
}

TEST(BcmAnalysis, PatternStopsWhenAsked) {
  const LargePlane p;
  const Regions regions = p.regions(0.001);
  const std::atomic<bool> go{false}, stop{true};
  EXPECT_GT(bcm_lower_pattern(p.mesh, regions, 3, &go).nonZeros(), 20 * regions.n_free());
  EXPECT_EQ(bcm_lower_pattern(p.mesh, regions, 3, &stop).rows(), 0);
}

// A cancel unwinding through the analysis must not wait for METIS (20 s at 1M free): the
// thread is held between the pattern and the ordering while the analysis, then the mesh and
// regions it read, are destroyed; released, it must not touch them (ASan would see it).
TEST(BcmAnalysis, DroppedWithoutWaitingForTheOrdering) {
  if (thread_budget() < 2) GTEST_SKIP() << "FREEFORM_THREADS=1: no analysis ahead";
  auto p = std::make_unique<LargePlane>();
  auto regions = std::make_unique<Regions>(p->regions(0.001));
  BcmSettings s;
  s.order = 3;
  auto entered = std::make_shared<std::promise<void>>();
  std::future<void> in_hook = entered->get_future();
  std::promise<void> release;
  std::shared_future<void> released = release.get_future().share();
  auto analysis = std::make_unique<BcmAnalysis>(p->mesh, *regions, s, kSmall, [entered, released] {
    entered->set_value();
    released.wait();
  });
  ASSERT_TRUE(analysis->started());
  ASSERT_EQ(in_hook.wait_for(std::chrono::seconds(60)), std::future_status::ready);
  std::future<void> dropped = std::async(std::launch::async, [&] {
    analysis.reset();
    regions.reset();
    p.reset();
  });
  const bool waited = dropped.wait_for(std::chrono::seconds(30)) != std::future_status::ready;
  release.set_value();
  dropped.wait();
  EXPECT_FALSE(waited) << "the destructor waited for the held thread";
}

}  // namespace
}  // namespace freeform::test
