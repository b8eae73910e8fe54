// Shared pieces of the Python module `freeform` (docs/python.md): one bind_* per concept and
// the conversions between numpy / Python objects and the library's types.
#pragma once

#include "freeform/common/json_reader.h"
#include "freeform/edit/edit.h"
#include "freeform/mesh/mesh.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace freeform::python {

namespace py = pybind11;

using MeshPtr = std::shared_ptr<const Mesh>;

// An edit resolved against a mesh (vertex lists); n_vertices is that mesh's vertex count.
struct PyEdit {
  Edit edit;
  int n_vertices = 0;
};

void bind_errors(py::module_& m);
void bind_mesh(py::module_& m);
void bind_mesh_file(py::module_& m);
void bind_edit(py::module_& m);
void bind_solver(py::module_& m);

// --- arrays.cpp: numpy in and out. `name` is the argument's name in messages. ---
// #V x 3 real numbers (any real dtype, any strides; converted to double). TypeError on a
// non-real dtype, ValueError on another shape.
std::vector<Vec3> to_positions(py::handle obj, const char* name);
// #F x 3 integers (any integer dtype). TypeError on a non-integer dtype, ValueError on another
// shape; freeform.Error on an index that does not fit an int.
std::vector<Tri> to_faces(py::handle obj, const char* name);
// One 4x4 affine matrix per movable handle: a sequence of 4x4 arrays or one (m, 4, 4) array.
// Writes `n` maps to `out`. TypeError / ValueError naming `name[i]`.
void to_transforms(py::handle obj, int n, Eigen::Affine3d* out, const char* name);
// os.fsdecode(obj): str, bytes or os.PathLike; TypeError naming `name` otherwise.
std::string to_path(py::handle obj, const char* name = "path");

py::array_t<double> positions_array(const Vec3* data, std::size_t n);  // new n x 3 array
py::array_t<std::int64_t> faces_array(const std::vector<Tri>& faces);          // new m x 3 array
py::array_t<double> matrix_array(const Eigen::Affine3d& t);            // new 4 x 4 array
py::array_t<std::int64_t> vertex_array(const std::vector<Vertex>& vertices);    // new 1-d array

// --- json_convert.cpp ---
py::object to_python(const Json& j);
// Python data (dict, list, tuple, str, int, float, bool, None, numpy scalars and arrays) as
// JSON. TypeError naming the path inside `name` for anything else.
Json to_json(py::handle obj, const std::string& name);

}  // namespace freeform::python
