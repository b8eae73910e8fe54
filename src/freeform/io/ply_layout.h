// Internal: what the PLY reader takes from a file's vertex and face elements (the role of each
// property, Layout), shared by the reader (ply.cpp) and the rewrite (ply_rewrite.cpp).
// Not part of the public API.
#pragma once

#include "freeform/io/mesh_attributes.h"
#include "freeform/io/ply_header.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace freeform::ply_detail {

// Property roles inside the vertex and face elements. NX..NZ are rewritten with recomputed
// normals; Attribute values go to Field::target.
enum class Role : std::uint8_t { Skip, X, Y, Z, Indices, NX, NY, NZ, Attribute };

inline bool is_position(Role r) { return r == Role::X || r == Role::Y || r == Role::Z; }
inline bool is_normal(Role r) { return r == Role::NX || r == Role::NY || r == Role::NZ; }
// The component of a position (X..Z) or normal (NX..NZ) role: 0, 1 or 2.
inline int component_of(Role r) {
  return static_cast<int>(r) - static_cast<int>(is_position(r) ? Role::X : Role::NX);
}

// Where a scalar property's value goes.
struct Field {
  Role role = Role::Skip;
  int target = -1;  // index into Layout::targets[element] (normals, uv, named attributes)
  int component = 0;
  double scale = 1;  // integer colours: 1 / the type's maximum
};

// One attribute row per entry: `width` values appended to `values` for every entry.
struct Target {
  std::vector<double>* values = nullptr;
  int width = 1;
};

struct Layout {
  std::size_t vertex_element = 0;
  std::size_t face_element = 0;
  std::uint64_t vertex_count = 0;
  std::vector<std::vector<Field>> fields;    // per element, per property
  std::vector<std::vector<Target>> targets;  // per element
};

// The vertex and face elements and their positions and vertex indices; throws IoError naming
// the file when the header lacks them or declares them twice.
Layout make_layout(const Header& header, const std::string& name);

// Binds normals, texture coordinates, colours and every other scalar property of the vertex
// and face elements to `attributes` (Layout::targets point into it).
void bind_attributes(const Header& header, Layout& layout, MeshAttributes& attributes);

// The file `data` as read, to rewrite its positions and normals (ply_rewrite.cpp);
// `vertex_offset` is where the vertex element starts in `data`.
std::shared_ptr<const FileSource> make_ply_source(std::shared_ptr<const std::string> data, const std::string& name,
                                                  const Header& header, const Layout& layout,
                                                  std::size_t vertex_offset);

}  // namespace freeform::ply_detail
