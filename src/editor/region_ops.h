// Operations on painted vertex regions (issue 4): grow and shrink by edge rings, a geodesic
// flood from a clicked vertex on the displayed geometry, and the connected pieces of a region.
// Regions are vertex sets; inputs may be in any order with repeats, outputs are sorted and
// unique. Invalid vertices and negative counts or radii throw InvalidInput.
#pragma once

#include "freeform/mesh/mesh.h"

#include <span>
#include <vector>

namespace freeform::editor {

// The set plus every vertex within `rings` edge hops of it (rings >= 0; 0 returns the set).
std::vector<Vertex> grow_rings(const Mesh& mesh, std::span<const Vertex> set, int rings);

// The set minus every vertex within `rings` edge hops of a vertex NOT in the set. The mesh
// boundary does not erode a region (only unselected vertices do), so shrinking a whole
// component of the mesh leaves it unchanged.
std::vector<Vertex> shrink_rings(const Mesh& mesh, std::span<const Vertex> set, int rings);

// Vertices whose shortest edge-path length from `seed` (Dijkstra over edge lengths measured
// on `positions`, one per vertex: the displayed, possibly deformed, geometry) is <= radius.
// Edge paths over-estimate surface distance by up to ~8% on regular grids (selectors.h).
std::vector<Vertex> geodesic_flood(const Mesh& mesh, const VertexData<Vec3>& positions, Vertex seed, double radius);

// The pieces of the set connected through mesh edges between set vertices: each piece sorted,
// pieces ordered by their smallest vertex.
std::vector<std::vector<Vertex>> region_components(const Mesh& mesh, std::span<const Vertex> set);

}  // namespace freeform::editor
