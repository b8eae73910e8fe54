// The frame at a base vertex that carries that vertex's own detail (docs/multires.md, "Vertex
// frames"). Its normal is the base's area-weighted vertex normal (the normal the paper's detail
// height is measured along, so heights are kept exactly); its tangent is read from the vertex's
// ring: with (x_j, y_j) the ring's rest 2D coordinates in the rest tangent plane
// (stencil_weights) and e_j the ring's offsets on the current base,
//     g = sum_j x_j e_j,   h = sum_j y_j e_j
// span the least-squares linear map from the rest tangent plane to the current base, and
// P g - n x h (P: projection onto the tangent plane) is the image of the rest x axis under that
// map's rotation part (the 2D Procrustes rotation). That follows twists about the normal as well
// as bends, is exact for rigid motions, and gives the rest frame at rest, so the identity edit
// reproduces the input to rounding.
#pragma once

#include "freeform/mesh/types.h"

#include <cmath>

namespace freeform::multires {

// Writes the stencil's weights (x_j, y_j) in the rest tangent plane of unit normal n at
// `center`, the x axis along the first stencil vertex's projected offset (any tangent where
// that vanishes). position(j) returns stencil vertex j's rest base position.
template <class Position, class Weight>
void stencil_weights(const Vec3& center, const Vec3& n, int count, Position position, Weight* weights) {
  Vec3 u = count > 0 ? Vec3(position(0) - center) : Vec3::Zero();
  u -= u.dot(n) * n;
  const double len = u.norm();
  u = len > 0.0 ? Vec3(u / len) : n.unitOrthogonal();
  const Vec3 v = n.cross(u);
  for (int j = 0; j < count; ++j) {
    const Vec3 e = position(j) - center;
    weights[2 * j] = static_cast<Weight>(e.dot(u));
    weights[2 * j + 1] = static_cast<Weight>(e.dot(v));
  }
}

// The tangent's direction: the image of the rest x axis under the Procrustes rotation of the map
// from the rest tangent plane to the current base, P g - n x h; normalized_or_zero makes it the
// tangent (zero if the ring collapsed).
inline Vec3 tangent_direction(const Vec3& g, const Vec3& h, const Vec3& n) { return g - g.dot(n) * n - n.cross(h); }

inline Vec3 normalized_or_zero(const Vec3& t) {
  const double tt = t.squaredNorm();
  return tt > 0.0 ? Vec3(t * (1.0 / std::sqrt(tt))) : Vec3::Zero();
}

// Each vertex's ring for the tangent: ring[offset[i] .. offset[i + 1]) are vertex i's neighbours
// (rows of the base) and weight[2 j], weight[2 j + 1] their stencil_weights.
struct RingStencil {
  const int* offset;
  const int* ring;
  const float* weight;
};

// Which compiled loop runs: the widest the CPU has (Auto), or the build's baseline (for tests
// that compare the two).
enum class FrameKernel { Auto, Baseline };

// For vertices lo..hi-1: t_i = tangent_direction(g_i, h_i, n_i), not normalized, with the ring
// moments g_i, h_i on the base b (rows x 3, row-major) and unit normals n (same layout).
void ring_tangents(const RingStencil& s, const double* b, int rows, const double* n, int lo, int hi, double* t,
                   FrameKernel kernel = FrameKernel::Auto);

// Where the detail goes: base rows b, unit normals n and tangent directions t (row-major x 3,
// with their row counts), the frame coordinates w (3 a vertex: along t, n x t and n), and each
// vertex's index among the output's.
struct FramePlacement {
  const double* b;
  int rows_b;
  const double* n;
  int rows_n;
  const double* t;
  int rows_t;
  const double* w;
  const int* global;
};

// out[global[i]] = b_i + w_i0 t_i + w_i1 n_i x t_i + w_i2 n_i for vertices lo..hi-1, with t_i
// the normalized tangent direction (zero where it vanished).
void place_in_frames(const FramePlacement& f, int lo, int hi, Vec3* out, FrameKernel kernel = FrameKernel::Auto);

}  // namespace freeform::multires
