// The two files of the Botsch-Sorkine deformation benchmark ("On Linear Variational Surface
// Deformation Methods", 2008), read by `freeform deform --sel --def` and by "sel" selectors.
//
// .sel: comment lines starting with '#', then one integer per line and vertex, in file order:
//       0 fixed, 1 free (support), 2 handle. The count must equal the mesh's vertex count.
// .def: a comment line (lines starting with '#'), then a 4x4 matrix, row-major, 16 numbers
//       (any whitespace), applied to column vectors: x' = M [x; 1].
// Errors are IoError "file:line: what is wrong".
#pragma once

#include <Eigen/Core>

#include <string>
#include <string_view>
#include <vector>

namespace freeform {

enum SelLabel : int { kSelFixed = 0, kSelFree = 1, kSelHandle = 2 };

// One label per vertex (n_vertices entries, each 0, 1 or 2). `name` is used in messages.
std::vector<int> parse_sel(std::string_view data, const std::string& name, int n_vertices);
std::vector<int> read_sel_file(const std::string& path, int n_vertices);

// The 4x4 matrix as written (no validity check of the transform itself; see
// affine_from_matrix in edit/manipulator.h).
Eigen::Matrix4d parse_def(std::string_view data, const std::string& name);
Eigen::Matrix4d read_def_file(const std::string& path);

}  // namespace freeform
