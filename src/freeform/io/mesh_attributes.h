// What a mesh file holds besides the welded triangles the solver works on: its polygons,
// texture coordinates, normals, colours and other properties, and the file itself, so that a
// deformed mesh is written back with only its positions (and normals) changed.
#pragma once

#include "freeform/mesh/types.h"

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace freeform {

// The file's faces as it wrote them (quads and n-gons stay whole), in soup vertex indices.
struct Polygons {
  std::vector<int> offsets{0};  // polygon p's corners are corners[offsets[p] .. offsets[p + 1])
  std::vector<int> corners;     // the soup vertex of each corner
  int size() const { return static_cast<int>(offsets.size()) - 1; }
  int corner_count(int p) const { return offsets[static_cast<std::size_t>(p) + 1] - offsets[static_cast<std::size_t>(p)]; }
  void add(std::span<const int> polygon) {
    corners.insert(corners.end(), polygon.begin(), polygon.end());
    offsets.push_back(static_cast<int>(corners.size()));
  }
};

// Values shared between polygon corners through an index, so that a seam (one vertex with two
// texture coordinates, or a crease with two normals) is kept. A per-vertex attribute of a
// format without corners (PLY, OFF) indexes its rows by the corner's vertex.
struct CornerAttribute {
  int width = 0;               // 2 for texture coordinates, 3 for normals
  std::vector<double> values;  // row-major: row r is values[r * width .. (r + 1) * width)
  std::vector<int> index;      // one row per corner of Polygons::corners; empty: no attribute
  bool empty() const { return index.empty(); }
  int rows() const { return width == 0 ? 0 : static_cast<int>(values.size()) / width; }
};

// One row per soup vertex (or per polygon for face attributes).
struct NamedAttribute {
  std::string name;  // "color" (components in 0..1, width 3 or 4) or the file's property name
  int width = 1;
  std::vector<double> values;  // row-major
};

struct MeshAttributes {
  Polygons polygons;                  // empty (size 0) when the reader kept none
  std::vector<int> triangle_polygon;  // soup face t was cut from polygon triangle_polygon[t]
  CornerAttribute uv;                 // texture coordinates, v up (OBJ's; glTF's v is flipped)
  CornerAttribute normal;             // the file's normals (recomputed on writing)
  std::vector<NamedAttribute> vertex;  // per soup vertex: "color", other PLY properties
  std::vector<NamedAttribute> face;    // per polygon: "color", other PLY properties
  const NamedAttribute* vertex_attribute(std::string_view name) const {
    for (const NamedAttribute& a : vertex)
      if (a.name == name) return &a;
    return nullptr;
  }
};

struct ReadResult;

// What a reader kept of the file to write the same file back: everything byte for byte except
// the positions (and the normals, recomputed for them). Implemented by each format's reader.
class FileSource {
 public:
  virtual ~FileSource() = default;
  // The file's content with `positions` (one per soup vertex) in place of the read ones.
  // Files beside the main one (a glTF's modified .bin) are returned in `companions` as
  // (path relative to the main file's folder, bytes).
  virtual std::string rewrite(const ReadResult& file, std::span<const Vec3> positions,
                              std::vector<std::pair<std::string, std::string>>& companions,
                              const std::string& out_path) const = 0;
  virtual bool binary() const { return false; }  // the file's encoding (PLY, .glb)
  // What only a rewrite keeps, named for the message when writing another format instead
  // (e.g. "groups, materials and smoothing groups"); empty when nothing.
  virtual std::string kept_only_by_rewrite() const { return {}; }
};

// The normals of a corner attribute recomputed for `positions`: row r becomes the normalized
// sum of the area-weighted normals of the polygons with a corner indexed r, so a split (a
// crease, a smoothing group) stays split. Rows no corner uses keep their value; with
// `old_positions` (those read), so do rows whose polygons all kept their positions.
std::vector<double> recomputed_normals(const Polygons& polygons, const CornerAttribute& normal,
                                       std::span<const Vec3> positions, std::span<const Vec3> old_positions = {});

// A corner attribute as one row per vertex (n_vertices rows; vertices without corners get 0),
// or nullopt when some vertex has different values at different corners (a seam): what
// formats with per-vertex attributes only (PLY, OFF, glTF's welded vertex) can store.
std::optional<std::vector<double>> per_vertex_values(const Polygons& polygons, const CornerAttribute& attribute,
                                                     int n_vertices);

// Fills polygons and triangle_polygon from a soup without attributes (one triangle each).
void polygons_from_triangles(const TriangleSoup& soup, MeshAttributes& attributes);

}  // namespace freeform
