// The regions of one edit (docs/bcm.md): the support, handle components inside it
// (movable with their own manipulator, or immovable), everything else fixed.
#pragma once

#include "freeform/mesh/mesh.h"

#include <cstdint>
#include <vector>

namespace freeform {

enum class Role : std::uint8_t { Fixed, Free, Handle };

struct HandleRegion {
  std::vector<Vertex> vertices;  // unique, sorted
  bool movable = true;           // false: immovable, acts like fixed surface (supports with holes)
};

class Regions {
 public:
  // `support`: vertices that may change; handle vertices belong to the support even if the
  // support selection missed them. Free = support minus handles.
  // Throws InvalidInput (naming the handle or vertex): empty support, a vertex index outside
  // the mesh, a handle without vertices, a vertex in two handles, no free vertex left.
  Regions(const Mesh& mesh, const std::vector<Vertex>& support, std::vector<HandleRegion> handles);

  Role role(Vertex v) const { return role_[v]; }
  int handle_of(Vertex v) const { return handle_[v]; }  // -1 unless role(v) == Handle
  const std::vector<Vertex>& free_vertices() const { return free_; }  // sorted by index
  const std::vector<HandleRegion>& handles() const { return handles_; }
  int n_vertices() const { return static_cast<int>(role_.size()); }
  int n_free() const { return static_cast<int>(free_.size()); }
  int n_fixed() const { return n_fixed_; }  // outside the support
  int n_movable() const { return n_movable_; }
  // Index of handle h among the movable handles (manipulator index), -1 if immovable.
  int movable_index(int h) const { return movable_index_[static_cast<std::size_t>(h)]; }

 private:
  VertexData<Role> role_;
  VertexData<int> handle_;
  std::vector<Vertex> free_;
  std::vector<HandleRegion> handles_;
  std::vector<int> movable_index_;
  int n_fixed_ = 0;
  int n_movable_ = 0;
};

}  // namespace freeform
