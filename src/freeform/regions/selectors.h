// Vertex selection for edit regions (docs/bcm.md): index lists, Euclidean spheres,
// geodesic disks (shortest edge paths) and .sel labels. Every selector returns sorted, unique
// vertices and throws InvalidInput naming the selector (`name`, e.g. "handles[0].region") if
// it selects nothing or is malformed.
#pragma once

#include "freeform/mesh/mesh.h"

#include <limits>
#include <span>
#include <string>
#include <vector>

namespace freeform {

// Vertices by 0-based index (file order). Throws for an empty list or an index outside
// [0, #V). Duplicates are allowed and removed.
std::vector<Vertex> select_indices(const Mesh& mesh, std::span<const long long> indices, const std::string& name);

// Vertices with |x - center| <= radius. radius must be finite and > 0.
std::vector<Vertex> select_sphere(const Mesh& mesh, const Vec3& center, double radius, const std::string& name);

// Vertices whose geodesic_distance from nearest_vertex(center) is <= radius (finite, > 0).
std::vector<Vertex> select_geodesic(const Mesh& mesh, const Vec3& center, double radius, const std::string& name);

// Vertices v with labels[v] in `wanted` (labels: one per vertex, e.g. from read_sel_file).
std::vector<Vertex> select_labels(std::span<const int> labels, std::span<const int> wanted, const std::string& name);

// The non-isolated vertex closest to p (Euclidean); ties go to the smaller index.
// Throws InvalidInput if the mesh has no face.
Vertex nearest_vertex(const Mesh& mesh, const Vec3& p);

// Length of the shortest path along mesh edges from `source` (Dijkstra), +inf where
// unreachable or beyond max_distance. O(n log n) in the number of vertices reached.
// This over-estimates the true surface distance by a factor that depends on the
// triangulation (<= ~1.08 on a regular grid with alternating diagonals).
VertexData<double> geodesic_distance(const Mesh& mesh, Vertex source,
                                     double max_distance = std::numeric_limits<double>::infinity());
// The same over edges measured on `positions` (#V entries, e.g. the displayed, deformed
// shape); `reached`, if given, receives the vertices with a finite distance in the order they
// are settled (cost O(reached log reached) beyond the #V distance array).
VertexData<double> geodesic_distance(const Mesh& mesh, const VertexData<Vec3>& positions, Vertex source,
                                     double max_distance, std::vector<Vertex>* reached = nullptr);

}  // namespace freeform
