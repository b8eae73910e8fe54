// Editor session files (issue 4): the mesh file, the edits applied so far (edit-file JSON,
// docs/edit-format.md, replayed with freeform::deform on load) and the current edit with its
// handle ids and manipulators, so a session reopens exactly where it was left:
//
//   {"version": 1,
//    "mesh": {"path": "/abs/plane.off", "relative": "plane.off", "vertices": 441},
//    "applied": [EDIT, ...],
//    "current": {"parameters": {"order": 3, "outer": 2.0, "inner": 2.0, "anisotropic": false,
//                               "multiresolution": true, "nonlinear": false,
//                               "preserve_volume": true,  // optional, default true
//                               "segments": [{"vertices": [...], "value": 0.0}]},  // optional
//                "support": [vertex, ...],          // painted support flags (handles add theirs)
//                "handles": [{"id": 0, "movable": true, "vertices": [...],
//                             "manipulator": {"translation": [x,y,z], "rotation": [w,x,y,z],
//                                             "scale": [x,y,z], "pivot": [x,y,z]},
//                             "matrix": [[4 numbers] x 4]}],   // matrix optional
//                "active_handle": 0}}               // -1: none
//
// Parsing is strict like edit files: unknown keys, wrong types, missing keys and values out
// of range are InvalidInput "FILE: ... KEY.PATH ..."; malformed JSON is IoError FILE:LINE.
#pragma once

#include "editor/edit_state.h"
#include "freeform/common/json_reader.h"
#include "freeform/edit/edit.h"
#include "freeform/io/mesh_io.h"
#include "freeform/mesh/mesh.h"

#include <string>
#include <string_view>
#include <vector>

namespace freeform::editor {

struct Session {
  std::string mesh_path;      // absolute path of the original mesh file
  std::string mesh_relative;  // the same, relative to the session file's folder
  int n_vertices = 0;         // of that mesh (a changed mesh file is refused)
  std::vector<Json> applied;  // edit objects, in the order they were applied
  EditState current;          // its n_vertices() must equal n_vertices
  int active_handle = -1;     // a handle id of `current` or -1
};

// The session as JSON text (doubles with full round-trip precision).
std::string session_text(const Session& session);
// Parses session text; `name` prefixes messages. Applied edits are checked to be objects only
// (their content is parsed against the mesh when replayed).
Session parse_session_text(std::string_view text, const std::string& name);

void write_session_file(const std::string& path, const Session& session);  // atomic (IoError)
Session read_session_file(const std::string& path);

// The mesh file to open: mesh_relative resolved against the session file's folder if that
// file exists, else mesh_path. IoError naming both if neither exists.
std::string session_mesh_file(const Session& session, const std::string& session_path);

// A session read and replayed: the mesh file read as Document::open does, each applied edit
// parsed against the mesh as it was then and replayed with deform() (the CLI's code), and
// the current edit with unset pivots resolved to the handle centroids. Throws like
// read_session_file, read_mesh, Mesh::from_soup, parse_edit and deform (messages name the
// session file and "applied[i]"); InvalidInput if the mesh's vertex count changed.
struct LoadedSession {
  std::string mesh_file;              // the file that was read
  std::vector<std::string> warnings;  // from the mesh reader
  std::shared_ptr<const ReadResult> file;  // everything it held (saving keeps it)
  Mesh rest;                          // the original with the applied edits baked in
  std::vector<Edit> applied;
  EditState current;
  int active_handle = -1;
};
LoadedSession load_session_file(const std::string& path);

}  // namespace freeform::editor
