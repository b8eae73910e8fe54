// The per-frame loops of vertex frames (vertex_frame.h), compiled for the build's baseline ISA
// and, on x86-64, for AVX2 + FMA (picked at run time, as the BCM basis product is): a row
// (x, y, z) is one 4-wide vector, so a ring moment is one FMA per neighbour.
#include "freeform/multires/vertex_frame.h"

#include "freeform/common/cpu_features.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace freeform::multires {
namespace {

using Map3 = Eigen::Map<const Vec3>;

void tangents_baseline(const RingStencil& s, const double* b, const double* n, int lo, int hi, double* t) {
  for (int i = lo; i < hi; ++i) {
    const double cx = b[3 * i], cy = b[3 * i + 1], cz = b[3 * i + 2];
    double gx = 0, gy = 0, gz = 0, hx = 0, hy = 0, hz = 0;  // scalar: Eigen's temporaries cost a third of the loop
    for (int j = s.offset[i]; j < s.offset[i + 1]; ++j) {
      const double* r = b + 3 * s.ring[j];
      const double ex = r[0] - cx, ey = r[1] - cy, ez = r[2] - cz;
      const double wx = s.weight[2 * j], wy = s.weight[2 * j + 1];
      gx += wx * ex, gy += wx * ey, gz += wx * ez;
      hx += wy * ex, hy += wy * ey, hz += wy * ez;
    }
    const Vec3 d = tangent_direction(Vec3(gx, gy, gz), Vec3(hx, hy, hz), Map3(n + 3 * i));
    t[3 * i] = d[0], t[3 * i + 1] = d[1], t[3 * i + 2] = d[2];
  }
}

void place_baseline(const FramePlacement& f, int lo, int hi, Vec3* out) {
  for (int i = lo; i < hi; ++i) {
    const Vec3 n = Map3(f.n + 3 * i), t = normalized_or_zero(Map3(f.t + 3 * i));
    const double* w = f.w + 3 * i;
    out[f.global[i]] = Map3(f.b + 3 * i) + w[0] * t + w[1] * n.cross(t) + w[2] * n;
  }
}

#if defined(__x86_64__) && defined(__GNUC__)
// Row r of b as (x, y, z, *): the fourth lane is the next row's x, or masked off on the last row.
[[gnu::target("avx2,fma")]] inline __m256d load_row(const double* b, int r, int rows) {
  if (r + 1 < rows) return _mm256_loadu_pd(b + 3 * r);
  return _mm256_maskload_pd(b + 3 * r, _mm256_set_epi64x(0, -1, -1, -1));
}

[[gnu::target("avx2,fma")]] void tangents_avx2(const RingStencil& s, const double* b, int rows, const double* n,
                                                int lo, int hi, double* t) {
  alignas(32) double g[4], h[4];
  for (int i = lo; i < hi; ++i) {
    const __m256d c = load_row(b, i, rows);
    __m256d vg = _mm256_setzero_pd(), vh = _mm256_setzero_pd();
    for (int j = s.offset[i]; j < s.offset[i + 1]; ++j) {
      const __m256d e = _mm256_sub_pd(load_row(b, s.ring[j], rows), c);
      vg = _mm256_fmadd_pd(_mm256_set1_pd(s.weight[2 * j]), e, vg);
      vh = _mm256_fmadd_pd(_mm256_set1_pd(s.weight[2 * j + 1]), e, vh);
    }
    _mm256_store_pd(g, vg);
    _mm256_store_pd(h, vh);
    const Vec3 d = tangent_direction(Vec3(g[0], g[1], g[2]), Vec3(h[0], h[1], h[2]), Map3(n + 3 * i));
    t[3 * i] = d[0], t[3 * i + 1] = d[1], t[3 * i + 2] = d[2];
  }
}

// (y, z, x, *) of (x, y, z, *): the cross product's operand order.
[[gnu::target("avx2,fma")]] inline __m256d yzx(__m256d v) { return _mm256_permute4x64_pd(v, 0xC9); }

[[gnu::target("avx2,fma")]] void place_avx2(const FramePlacement& f, int lo, int hi, Vec3* out) {
  for (int i = lo; i < hi; ++i) {
    const __m256d n = load_row(f.n, i, f.rows_n), t = load_row(f.t, i, f.rows_t);
    const __m128d tt2 = _mm_mul_pd(_mm256_castpd256_pd128(t), _mm256_castpd256_pd128(t));
    const double tz = f.t[3 * i + 2];
    const double tt = _mm_cvtsd_f64(_mm_add_sd(tt2, _mm_unpackhi_pd(tt2, tt2))) + tz * tz;
    const double s = tt > 0.0 ? 1.0 / std::sqrt(tt) : 0.0;
    const double* w = f.w + 3 * i;
    const __m256d nxt = _mm256_fmsub_pd(yzx(n), yzx(yzx(t)), _mm256_mul_pd(yzx(yzx(n)), yzx(t)));  // n x t
    __m256d x = _mm256_fmadd_pd(_mm256_set1_pd(w[2]), n, load_row(f.b, i, f.rows_b));
    x = _mm256_fmadd_pd(_mm256_set1_pd(w[0] * s), t, x);
    x = _mm256_fmadd_pd(_mm256_set1_pd(w[1] * s), nxt, x);
    double* o = out[f.global[i]].data();  // three doubles: the next vertex's belong to another thread
    _mm_storeu_pd(o, _mm256_castpd256_pd128(x));
    _mm_store_sd(o + 2, _mm256_extractf128_pd(x, 1));
  }
}

const bool kHasAvx2 = cpu_has_avx2_fma();
#endif

}  // namespace

void ring_tangents(const RingStencil& s, const double* b, int rows, const double* n, int lo, int hi, double* t,
                   FrameKernel kernel) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (kHasAvx2 && kernel == FrameKernel::Auto) {
    tangents_avx2(s, b, rows, n, lo, hi, t);
    return;
  }
#else
  (void)rows, (void)kernel;
#endif
  tangents_baseline(s, b, n, lo, hi, t);
}

void place_in_frames(const FramePlacement& f, int lo, int hi, Vec3* out, FrameKernel kernel) {
#if defined(__x86_64__) && defined(__GNUC__)
  if (kHasAvx2 && kernel == FrameKernel::Auto) {
    place_avx2(f, lo, hi, out);
    return;
  }
#else
  (void)kernel;
#endif
  place_baseline(f, lo, hi, out);
}

}  // namespace freeform::multires
