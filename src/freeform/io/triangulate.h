// How the readers cut a polygon into triangles. A fan from the first corner puts all n - 2
// triangles on that corner: a CAD disc or a cylinder's cap of 1,024 corners gives it 1,025
// neighbours, whose rows of the order-k operator then hold thousands of vertices
// (bcm/stencil_check.h). A convex polygon of more than kFanCorners corners is instead cut into a
// strip (triangles alternately on either side of a chord moving across it), which leaves each
// corner in at most four triangles. Its triangles have the fan's angles (on a circle: one of
// pi / n, two near 90 degrees, and two flat ears); halving it recursively instead put n / 2
// flat ears on the rim, whose cotangents near -n / 3 fold a bent cap. Smaller or non-convex
// polygons keep the fan.
#pragma once

#include "freeform/mesh/types.h"

#include <cstddef>
#include <span>
#include <vector>

namespace freeform::io_detail {

inline constexpr std::size_t kFanCorners = 8;

// Appends poly.size() - 2 triangles of the polygon (corner indices into `positions`) to faces,
// with the polygon's orientation. Returns true if it was cut into a strip rather than fanned (a corner
// outside `positions`, e.g. a PLY file that lists its faces before its vertices, gives a fan).
bool triangulate_polygon(const std::vector<int>& poly, std::span<const Vec3> positions, std::vector<Tri>& faces);

}  // namespace freeform::io_detail
