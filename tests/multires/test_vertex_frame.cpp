// Vertex frames' per-frame kernels (multires/vertex_frame.h): the wide (AVX2 + FMA) loops agree
// with the baseline ones to rounding, also on the last rows (whose fourth lane is masked), and
// the tangent follows a rigid motion of the ring exactly.
#include "freeform/multires/vertex_frame.h"

#include "freeform/common/cpu_features.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <random>
#include <vector>

using namespace freeform;
using namespace freeform::multires;

namespace {

// A random point cloud and, for each of its first `vertices` rows, a ring of 3-9 other rows with
// stencil weights; unit normals for every row.
struct Rings {
  std::vector<double> b, n;
  std::vector<int> offset{0}, ring;
  std::vector<float> weight;
  int rows = 0, vertices = 0;
  RingStencil stencil() const { return {offset.data(), ring.data(), weight.data()}; }
};

Rings random_rings(int rows, int vertices, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> valence(3, 9), row(0, rows - 1);
  Rings r;
  r.rows = rows, r.vertices = vertices;
  for (int i = 0; i < rows; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng)), n = Vec3(u(rng), u(rng), u(rng)).normalized();
    r.b.insert(r.b.end(), p.data(), p.data() + 3);
    r.n.insert(r.n.end(), n.data(), n.data() + 3);
  }
  for (int i = 0; i < vertices; ++i) {
    const int count = valence(rng);
    for (int j = 0; j < count; ++j) r.ring.push_back(j == 0 ? rows - 1 : row(rng));  // the last row in every ring
    r.offset.push_back(static_cast<int>(r.ring.size()));
  }
  r.weight.resize(2 * r.ring.size());
  const auto pos = [&](int k) { return Vec3(Eigen::Map<const Vec3>(r.b.data() + 3 * k)); };
  for (int i = 0; i < vertices; ++i)
    stencil_weights(pos(i), Vec3(Eigen::Map<const Vec3>(r.n.data() + 3 * i)), r.offset[i + 1] - r.offset[i],
                    [&](int j) { return pos(r.ring[static_cast<std::size_t>(r.offset[i] + j)]); },
                    r.weight.data() + 2 * r.offset[i]);
  return r;
}

}  // namespace

TEST(VertexFrameKernels, WideLoopsAgreeWithTheBaselineToRounding) {
  if (!cpu_has_avx2_fma()) GTEST_SKIP() << "this CPU runs the baseline loops only";
  for (const int rows : {1, 2, 7, 40}) {
    const Rings r = random_rings(rows, rows, 11u + static_cast<unsigned>(rows));  // every row a vertex: the last is masked
    std::vector<double> wide(3 * static_cast<std::size_t>(rows)), base(wide.size());
    ring_tangents(r.stencil(), r.b.data(), rows, r.n.data(), 0, rows, wide.data(), FrameKernel::Auto);
    ring_tangents(r.stencil(), r.b.data(), rows, r.n.data(), 0, rows, base.data(), FrameKernel::Baseline);
    for (std::size_t k = 0; k < wide.size(); ++k) EXPECT_NEAR(wide[k], base[k], 1e-13) << "rows " << rows << ", entry " << k;

    std::vector<double> w(3 * static_cast<std::size_t>(rows));
    std::vector<int> global(static_cast<std::size_t>(rows));
    for (int i = 0; i < rows; ++i) {
      w[3 * static_cast<std::size_t>(i)] = 0.3 * i, w[3 * static_cast<std::size_t>(i) + 1] = -0.2, w[3 * static_cast<std::size_t>(i) + 2] = 0.1;
      global[static_cast<std::size_t>(i)] = rows - 1 - i;  // scattered, reversed
    }
    const FramePlacement f{r.b.data(), rows, r.n.data(), rows, base.data(), rows, w.data(), global.data()};
    std::vector<Vec3> out_wide(static_cast<std::size_t>(rows + 1), Vec3::Constant(7.0)), out_base = out_wide;
    place_in_frames(f, 0, rows, out_wide.data(), FrameKernel::Auto);
    place_in_frames(f, 0, rows, out_base.data(), FrameKernel::Baseline);
    for (int i = 0; i <= rows; ++i)
      EXPECT_LT((out_wide[static_cast<std::size_t>(i)] - out_base[static_cast<std::size_t>(i)]).norm(), 1e-13) << "rows " << rows << ", output " << i;
    EXPECT_EQ(out_wide[static_cast<std::size_t>(rows)], Vec3::Constant(7.0)) << "wrote past the three doubles of the last output";
  }
}

TEST(VertexFrameKernels, TangentFollowsARigidMotionOfTheRing) {
  const Rings rest = random_rings(30, 20, 5u);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(2.1, Vec3(1, -2, 0.5).normalized()).toRotationMatrix();
  const Vec3 shift(3, -1, 2);
  Rings moved = rest;
  for (int k = 0; k < rest.rows; ++k) {
    Eigen::Map<Vec3>(moved.b.data() + 3 * k) = R * Eigen::Map<const Vec3>(rest.b.data() + 3 * k) + shift;
    Eigen::Map<Vec3>(moved.n.data() + 3 * k) = R * Eigen::Map<const Vec3>(rest.n.data() + 3 * k);
  }
  for (const FrameKernel kernel : {FrameKernel::Auto, FrameKernel::Baseline}) {
    std::vector<double> t0(3 * 20), t1(3 * 20);
    ring_tangents(rest.stencil(), rest.b.data(), rest.rows, rest.n.data(), 0, 20, t0.data(), kernel);
    ring_tangents(moved.stencil(), moved.b.data(), moved.rows, moved.n.data(), 0, 20, t1.data(), kernel);
    for (int i = 0; i < 20; ++i) {
      const Vec3 a = R * Eigen::Map<const Vec3>(t0.data() + 3 * i), b = Eigen::Map<const Vec3>(t1.data() + 3 * i);
      EXPECT_LT((a - b).norm(), 1e-12 * (1.0 + a.norm())) << "vertex " << i;
    }
  }
}
