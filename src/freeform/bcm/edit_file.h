// Edit files (docs/edit-format.md): the public batch interface of `freeform deform`.
// Parsing is strict: an unknown key, a wrong type, a missing required key or a value out of
// range is an InvalidInput "FILE: what is wrong at KEY.PATH" (e.g.
// `edit.json: unknown key "handles[0].transfrom"`); malformed JSON is an IoError
// "FILE:LINE:COLUMN: ...". Selectors are resolved against the mesh while parsing, so the
// returned Edit holds vertex lists.
#pragma once

#include "freeform/bcm/edit.h"
#include "freeform/regions/regions.h"

#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace freeform {

// Reads and parses an edit file; "sel" selector paths are relative to the file's folder.
Edit read_edit_file(const std::string& path, const Mesh& mesh);

// Parses edit-file text. `name` is used in messages, `base_dir` resolves "sel" paths.
Edit parse_edit_text(std::string_view text, const Mesh& mesh, const std::string& name,
                     const std::filesystem::path& base_dir);

// Parses an already-parsed JSON document.
Edit parse_edit(const nlohmann::json& j, const Mesh& mesh, const std::string& name,
                const std::filesystem::path& base_dir);

// The Botsch-Sorkine benchmark pair (regions/sel_file.h): support = labels {1, 2}, one
// movable handle = label 2 moved by the .def matrix. order in {1, 2, 3}, default smoothness.
Edit edit_from_sel_def(const std::string& sel_path, const std::string& def_path, int order, const Mesh& mesh);

// Throws InvalidInput for what deform() cannot do yet (multiresolution).
void check_edit_available(const Edit& edit);

// The Regions of an edit: its support and its handles in file order (fixed -> immovable).
// Throws InvalidInput as Regions does.
Regions edit_regions(const Mesh& mesh, const Edit& edit);

}  // namespace freeform
