// freeform.MeshFile: a mesh file as read, with its polygons and attributes as read-only numpy
// arrays; write_mesh_file(path, file, vertices) writes it back with new positions, keeping them.
#include "bindings.h"

#include "freeform/io/mesh_io.h"
#include "freeform/io/repair.h"

#include <pybind11/stl.h>

namespace freeform::python {
namespace {

struct MeshFile {
  std::shared_ptr<const ReadResult> file;
  std::shared_ptr<Mesh> mesh;
};

template <class T>
py::array_t<T> read_only(const T* data, std::size_t rows, std::size_t width, bool matrix = true) {
  py::array_t<T> a = matrix ? py::array_t<T>({rows, width}) : py::array_t<T>(rows);
  std::copy(data, data + rows * width, a.mutable_data());
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::array_t<std::int64_t> ints(const std::vector<int>& values) {
  std::vector<std::int64_t> wide(values.begin(), values.end());
  return read_only(wide.data(), wide.size(), 1, false);
}

py::object corner_attribute(const CornerAttribute& c) {
  if (c.empty()) return py::none();
  return py::make_tuple(read_only(c.values.data(), static_cast<std::size_t>(c.rows()), static_cast<std::size_t>(c.width)),
                        ints(c.index));
}

py::dict named(const std::vector<NamedAttribute>& attributes) {
  py::dict out;
  for (const NamedAttribute& a : attributes) {
    const auto width = static_cast<std::size_t>(a.width);
    out[py::str(a.name)] = read_only(a.values.data(), a.values.size() / width, width);
  }
  return out;
}

}  // namespace

void bind_mesh_file(py::module_& m) {
  py::class_<MeshFile>(m, "MeshFile",
                       "A mesh file as read by read_mesh_file: the welded triangle Mesh the solver works on, "
                       "and the polygons, texture coordinates, normals, colours and other properties of the file "
                       "(read-only arrays). write_mesh_file(path, file, vertices) writes it back with new "
                       "positions, keeping everything else.")
      .def_property_readonly("mesh", [](const MeshFile& self) { return self.mesh; }, "The triangle Mesh (file vertex order).")
      .def_property_readonly("format", [](const MeshFile& self) { return std::string(format_name(self.file->format)); },
                             "'obj', 'off', 'ply', 'stl' or 'gltf'.")
      .def_property_readonly("warnings", [](const MeshFile& self) { return self.file->warnings; }, "The reader's warnings.")
      .def_property_readonly("polygon_offsets", [](const MeshFile& self) { return ints(self.file->attributes.polygons.offsets); },
                             "(p + 1,) int64: polygon i's corners are polygon_corners[offsets[i]:offsets[i + 1]].")
      .def_property_readonly("polygon_corners", [](const MeshFile& self) { return ints(self.file->attributes.polygons.corners); },
                             "(c,) int64: the vertex of each polygon corner.")
      .def_property_readonly("uv", [](const MeshFile& self) { return corner_attribute(self.file->attributes.uv); },
                             "None, or (values (r, 2) float64, index (c,) int64: the row of each polygon corner, -1 none).")
      .def_property_readonly("normals", [](const MeshFile& self) { return corner_attribute(self.file->attributes.normal); },
                             "None, or (values (r, 3) float64, index (c,) int64), as uv.")
      .def_property_readonly("vertex_attributes", [](const MeshFile& self) { return named(self.file->attributes.vertex); },
                             "name -> (n, width) float64 per vertex: 'color' (0..1) and the file's other properties.")
      .def_property_readonly("face_attributes", [](const MeshFile& self) { return named(self.file->attributes.face); },
                             "name -> (p, width) float64 per polygon.")
      .def("__repr__", [](const MeshFile& self) {
        return "<freeform.MeshFile " + std::string(format_name(self.file->format)) + " with " +
               std::to_string(self.file->soup.positions.size()) + " vertices, " +
               std::to_string(self.file->attributes.polygons.size()) + " polygons>";
      });

  m.def(
      "read_mesh_file",
      [](py::handle path, bool repair_mesh) {
        const std::string p = to_path(path);
        MeshFile out;
        std::vector<std::string> warnings;
        {
          py::gil_scoped_release release;
          auto read = std::make_shared<ReadResult>(read_mesh(p));
          warnings = read->warnings;
          if (repair_mesh) {
            std::string lost;
            const BuildReport report = repair(*read, p, lost);
            for (const std::string& c : report.changes) warnings.push_back("repair: " + c);
            if (!lost.empty()) warnings.push_back("repair: " + lost);
          }
          out.mesh = std::make_shared<Mesh>(Mesh::from_soup(read->soup));
          out.file = std::move(read);
        }
        for (const std::string& w : warnings)
          if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) != 0) throw py::error_already_set();
        return out;
      },
      py::arg("path"), py::kw_only(), py::arg("repair") = false,
      "Reads OBJ, OFF, PLY, STL or glTF (by extension) with everything it holds. Raises IoError 'file:line: message', "
      "TopologyError for a non-manifold mesh unless repair=True: then vertices where several fans meet are split "
      "(copies appended) and faces that repeat a vertex dropped, polygons, texture coordinates and colours carried "
      "along, each change a UserWarning.");
  m.def(
      "write_mesh_file",
      [](py::handle path, const MeshFile& source, py::handle vertices, py::object binary) {
        const std::string p = to_path(path);
        const std::vector<Vec3> positions = to_positions(vertices, "vertices");
        WriteOptions options;
        // py::object, not std::optional<bool>: gcc 12 warns that the caster's optional may be
        // uninitialized (a false positive under -Werror).
        if (!binary.is_none()) options.binary = binary.cast<bool>();
        py::gil_scoped_release release;
        return write_mesh(p, *source.file, positions, options);
      },
      py::arg("path"), py::arg("source"), py::arg("vertices"), py::kw_only(), py::arg("binary") = py::none(),
      "Writes `source` (a MeshFile) with `vertices` ((n, 3), one per vertex of source.mesh) as positions, atomically. "
      "In the source's format and encoding everything but positions and normals is kept byte for byte; another "
      "format gets what it can hold. Returns what it could not hold (list of str).");
}

}  // namespace freeform::python
