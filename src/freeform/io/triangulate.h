// How the readers cut a polygon into triangles. A fan from the first corner is the common
// choice, and it stays for small convex polygons (quads, and anything where the rules below do
// not apply). Two cases get other cuts:
// - A convex polygon of more than kFanCorners corners is cut into a strip (triangles alternately
//   on either side of a chord moving across it), which leaves each corner in at most four
//   triangles. A fan puts all n - 2 on its first corner: a CAD disc or a cylinder's cap of 1,024
//   corners gives it 1,025 neighbours, and the order-k operator's rows there thousands of
//   vertices (bcm/stencil_check.h). The strip has the fan's angles (on a circle: one of pi / n,
//   two near 90 degrees, and two flat ears); halving the polygon recursively instead put n / 2
//   flat ears on the rim, whose cotangents near -n / 3 fold a bent cap.
// - A non-convex polygon (a star, an L, a letter's outline) is cut by ear clipping in the
//   coordinate plane most nearly parallel to it. Its fan overlaps itself: triangles outside the
//   outline, folded over each other, drawn and deformed as the surface. A polygon that repeats
//   a corner (a keyhole) or crosses itself keeps the fan (the mesh repair then splits it).
#pragma once

#include "freeform/mesh/types.h"

#include <cstddef>
#include <span>
#include <vector>

namespace freeform::io_detail {

inline constexpr std::size_t kFanCorners = 8;
// Above this many corners a non-convex polygon keeps the fan (ear clipping takes time
// quadratic in the corners).
inline constexpr std::size_t kMaxEarCorners = 4096;

enum class Cut { Fan, Strip, Ears };

// Appends poly.size() - 2 triangles of the polygon (corner indices into `positions`) to faces,
// with the polygon's orientation, and says how it was cut (a corner outside `positions`, e.g. a
// PLY file that lists its faces before its vertices, gives a fan).
Cut triangulate_polygon(const std::vector<int>& poly, std::span<const Vec3> positions, std::vector<Tri>& faces);

}  // namespace freeform::io_detail
