// Folded edges (docs/multires.md, "Folded edges"): interior edges whose dihedral angle, the angle between
// the normals of their two faces, grew by more than a threshold against the rest positions: a
// tear, fold or crease an edit created. A face that collapsed to zero area folds its edges.
#pragma once

#include "freeform/mesh/mesh.h"

#include <span>
#include <vector>

namespace freeform {

inline constexpr double kFoldDegrees = 60.0;  // the default threshold

// Precomputes the rest angles of the edges an edit can change (those with a face touching a
// moving vertex); count() is O(watched edges) and allocation-free, for per-frame use.
class FoldCounter {
 public:
  FoldCounter() = default;
  FoldCounter(const Mesh& mesh, const VertexData<Vec3>& rest, std::span<const Vertex> moving,
              double threshold_degrees = kFoldDegrees);

  // Watched edges whose dihedral angle in `positions` exceeds the rest angle by the threshold.
  int count(const VertexData<Vec3>& positions) const;
  int n_watched() const { return static_cast<int>(rest_angle_.size()); }

 private:
  std::vector<std::array<int, 4>> quads_;  // per edge: its ends (0, 1) and the opposite corners
  std::vector<double> rest_angle_;         // radians
  double threshold_ = 0;                   // radians
  int n_vertices_ = 0;
};

// One-shot: folded edges of the whole mesh between `rest` and `deformed`.
int count_folded_edges(const Mesh& mesh, const VertexData<Vec3>& rest, const VertexData<Vec3>& deformed,
                       double threshold_degrees = kFoldDegrees);

}  // namespace freeform
