// Edit files (docs/edit-format.md), the only place that knows their format: reading (strict:
// an unknown key, a wrong type, a missing required key or a value out of range is an
// InvalidInput "FILE: what is wrong at KEY.PATH", e.g. `edit.json: unknown key
// "handles[0].transfrom"`; malformed JSON is an IoError "FILE:LINE: ... column C ..."), the
// Botsch-Sorkine .sel/.def pair, and writing. Selectors are resolved against the mesh while
// parsing, so the returned Edit holds vertex lists.
#pragma once

#include "freeform/common/json_reader.h"
#include "freeform/edit/edit.h"
#include "freeform/mesh/mesh.h"

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

namespace freeform {

// Reads and parses an edit file; "sel" selector paths are relative to the file's folder.
Edit read_edit_file(const std::string& path, const Mesh& mesh);

// Parses edit-file text. `name` is used in messages, `base_dir` resolves "sel" paths.
Edit parse_edit_text(std::string_view text, const Mesh& mesh, const std::string& name,
                     const std::filesystem::path& base_dir);

// Parses an already-parsed JSON document.
Edit parse_edit(const Json& j, const Mesh& mesh, const std::string& name, const std::filesystem::path& base_dir);

// The Botsch-Sorkine benchmark pair (regions/sel_file.h): support = labels {1, 2}, one
// movable handle = label 2 moved by the .def matrix. order in {1, 2, 3}, default smoothness.
Edit edit_from_sel_def(const std::string& sel_path, const std::string& def_path, int order, const Mesh& mesh);

// The keys of an edit file that hold its settings (EditSettings): all but "support" and "handles".
inline constexpr std::array<const char*, 7> kEditSettingsKeys = {
    "order", "smoothness", "anisotropic", "multiresolution", "deformation", "nonlinear", "allow_unanchored"};

// Reads the settings keys of `j` (edit-file keys, the same checks and messages as
// parse_edit; `name` names the document in them). Any other key must be in `extra`;
// "smoothness.segments" is accepted and left to the caller (it needs the regions).
EditSettings parse_edit_settings(const Json& j, const std::string& name, std::span<const char* const> extra = {});

// The settings as edit-file keys, without segments: order, smoothness (outer, inner),
// anisotropic, multiresolution, deformation, nonlinear (where the model is nonlinear or its
// options are not the defaults) and allow_unanchored (where true).
Json edit_settings_to_json(const EditSettings& settings);

// The edit as edit-file JSON: explicit order, smoothness, anisotropic, multiresolution and
// deformation; {"vertices": [...]} selectors; "matrix" transforms with full round-trip
// precision (a movable handle without matrix but with a pivot is written as its matrix), so
// parse_edit(edit_to_json(e)) deforms bit for bit like e.
Json edit_to_json(const Edit& edit);

// Writes edit_to_json(edit) atomically (IoError on failure).
void write_edit_file(const std::string& path, const Edit& edit);

}  // namespace freeform
