// A mesh file as read, repaired (Mesh::from_soup with BuildOptions::repair: vertices split where
// several fans meet, faces with a repeated index dropped) with what else it held carried along:
// its polygons take the split vertices their triangles use, each added vertex gets its origin's
// per-vertex rows (colours, properties), and a polygon whose triangles were all dropped goes with
// its corner and face rows. Texture coordinates and normals stay those of each corner.
#pragma once

#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"

namespace freeform {

// Repairs `file` in place and returns what changed. When nothing did, the file is untouched and
// can still be written back byte for byte; otherwise its source is dropped (a rewrite cannot add
// vertices), so what only a rewrite keeps (FileSource::kept_only_by_rewrite, e.g. OBJ's groups
// and materials) is lost: `lost` is then the sentence that says so, empty when nothing is.
// Throws TopologyError naming `path` when no face would be left.
BuildReport repair(ReadResult& file, const std::string& path, std::string& lost);

// The mesh of a file as read, unrepaired (`freeform deform`, the editor: vertex order and faces
// kept exactly); a non-manifold one is refused with a TopologyError naming `path` and the command
// that writes a repaired copy keeping its attributes.
Mesh manifold_mesh(const TriangleSoup& soup, const std::string& path);

}  // namespace freeform
