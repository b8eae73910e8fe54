// Validation of a triangle soup: everything that is wrong or unusual, with element indices,
// plus the topology (boundary loops, components, Euler characteristic, genus).
#pragma once

#include "freeform/mesh/types.h"

#include <array>
#include <vector>

namespace freeform {

struct ComponentSummary {
  int vertices = 0, edges = 0, faces = 0, boundary_loops = 0;
  int euler_characteristic = 0;  // V - E + F
  int genus = 0;                 // (2 - chi - boundary_loops) / 2
};

struct ValidationReport {
  int vertices = 0, faces = 0;
  std::vector<std::array<int, 2>> nonmanifold_edges;   // vertex pairs shared by more than two faces
  std::vector<std::array<int, 2>> inconsistent_edges;  // two faces traverse the edge in the same direction
  std::vector<int> nonmanifold_vertices;               // vertices whose faces form several fans
  std::vector<int> repeated_index_faces;               // faces like (3, 3, 7)
  std::vector<int> zero_area_faces;                    // 2 area <= 1e-12 * longest edge^2
  std::vector<int> unreferenced_vertices;              // in no face
  std::vector<std::array<int, 2>> duplicate_vertices;  // (first, later) at exactly the same position

  // Topology of the surface as Mesh::from_soup builds it with repair (faces with a repeated
  // index dropped, non-manifold vertices split); for manifold input, of the input itself.
  // Unreferenced vertices are not counted here.
  std::vector<ComponentSummary> components;
  int boundary_loops = 0;
  int euler_characteristic = 0;
  int genus = 0;  // sum over components

  bool manifold() const {
    return nonmanifold_edges.empty() && inconsistent_edges.empty() && nonmanifold_vertices.empty() &&
           repeated_index_faces.empty();
  }
};

// Throws InvalidInput for indices out of range or non-finite positions (not a mesh at all).
ValidationReport validate(const TriangleSoup& soup);

// Pairs (first, later) of indices at exactly the same position (-0 equal to +0).
std::vector<std::array<int, 2>> coincident_positions(const std::vector<Vec3>& positions);

}  // namespace freeform
