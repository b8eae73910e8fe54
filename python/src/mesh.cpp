// freeform.Mesh (a halfedge mesh built from (V, F) arrays), read_mesh / write_mesh and the
// generated meshes of mesh/generators.h.
#include "bindings.h"

#include "freeform/io/mesh_io.h"
#include "freeform/mesh/generators.h"

#include <pybind11/stl.h>


namespace freeform::python {
namespace {

void warn(const std::string& message) {
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
}

std::shared_ptr<Mesh> build(TriangleSoup soup, bool repair) {
  BuildOptions options;
  options.repair = repair;
  BuildReport report;
  std::shared_ptr<Mesh> mesh;
  {
    py::gil_scoped_release release;
    mesh = std::make_shared<Mesh>(Mesh::from_soup(soup, options, &report));
  }
  for (const std::string& change : report.changes) warn("repair: " + change);
  return mesh;
}

std::vector<Tri> mesh_faces(const Mesh& mesh) {
  std::vector<Tri> faces;
  faces.reserve(static_cast<std::size_t>(mesh.n_faces()));
  for (Face f : mesh.faces()) {
    const auto v = mesh.vertices(f);
    faces.push_back({v[0].idx(), v[1].idx(), v[2].idx()});
  }
  return faces;
}

}  // namespace

void bind_mesh(py::module_& m) {
  py::class_<Mesh, std::shared_ptr<Mesh>>(m, "Mesh",
                                          "A 2-manifold, consistently oriented triangle mesh with double positions.")
      .def(py::init([](py::handle vertices, py::handle faces, bool repair) {
             return build({to_positions(vertices, "vertices"), to_faces(faces, "faces")}, repair);
           }),
           py::arg("vertices"), py::arg("faces"), py::kw_only(), py::arg("repair") = false,
           "vertices: n x 3 real numbers, faces: m x 3 vertex indices (counter-clockwise). Copies both. "
           "Raises TopologyError for non-manifold input unless repair=True (which splits vertices and drops "
           "degenerate faces, with a warning per change), Error for bad indices or non-finite positions.")
      .def_property_readonly(
          "vertices", [](const Mesh& self) { return positions_array(self.positions().raw().data(), self.positions().size()); },
          "n x 3 float64 array: a new copy of the positions.")
      .def_property_readonly("faces", [](const Mesh& self) { return faces_array(mesh_faces(self)); },
                             "m x 3 int64 array: a new copy of the triangles.")
      .def_property_readonly("n_vertices", &Mesh::n_vertices, "Number of vertices (rows of `vertices`).")
      .def_property_readonly("n_faces", &Mesh::n_faces, "Number of triangles (rows of `faces`).")
      .def_property_readonly("n_edges", &Mesh::n_edges, "Number of edges.")
      .def("__repr__", [](const Mesh& self) {
        return "<freeform.Mesh with " + std::to_string(self.n_vertices()) + " vertices, " +
               std::to_string(self.n_faces()) + " faces>";
      });

  m.def(
      "read_mesh",
      [](py::handle path, bool repair) {
        const std::string p = to_path(path);
        ReadResult read;
        {
          py::gil_scoped_release release;
          read = read_mesh(p);
        }
        for (const std::string& w : read.warnings) warn(w);
        return build(std::move(read.soup), repair);
      },
      py::arg("path"), py::kw_only(), py::arg("repair") = false,
      "Reads OBJ, OFF, PLY, STL or glTF (by extension) into a Mesh (read_mesh_file keeps the file's attributes). Raises IoError 'file:line: message'.");
  m.def(
      "write_mesh",
      [](py::handle path, py::handle vertices, py::handle faces, py::object binary) {
        const std::string p = to_path(path);
        TriangleSoup soup;
        if (py::isinstance<Mesh>(vertices) && faces.is_none()) {
          soup = vertices.cast<const Mesh&>().to_soup();
        } else {
          if (faces.is_none()) throw py::type_error("write_mesh: faces missing (pass vertices and faces, or a Mesh)");
          soup = {to_positions(vertices, "vertices"), to_faces(faces, "faces")};
        }
        WriteOptions options;
        // py::object, not std::optional<bool>: gcc 12 warns that the caster's optional may be
        // uninitialized (a false positive under -Werror).
        if (!binary.is_none()) options.binary = binary.cast<bool>();
        py::gil_scoped_release release;
        write_mesh(p, soup, options);
      },
      py::arg("path"), py::arg("vertices"), py::arg("faces") = py::none(), py::kw_only(), py::arg("binary") = py::none(),
      "Writes (vertices: (n, 3) real numbers, faces: (m, 3) integers) or a Mesh as OBJ, OFF, PLY, STL or glTF (by extension; binary PLY/STL unless "
      "binary=False; write_mesh_file keeps a file's attributes) atomically: a temporary file renamed over `path`. OFF, OBJ and PLY keep doubles exactly, "
      "STL stores float32.");

  m.def("make_plane", [](int nx, int ny, double w, double h) { return build(make_plane(nx, ny, w, h), false); },
        py::arg("nx"), py::arg("ny"), py::arg("width") = 1.0, py::arg("height") = 1.0,
        "Grid on [0, width] x [0, height] in z = 0: (nx+1)(ny+1) vertices, row-major.");
  m.def(
      "make_bumpy_plane",
      [](int nx, int ny, double amplitude, double frequency, double w, double h) {
        return build(make_bumpy_plane(nx, ny, amplitude, frequency, w, h), false);
      },
      py::arg("nx"), py::arg("ny"), py::arg("amplitude"), py::arg("frequency"), py::arg("width") = 1.0,
      py::arg("height") = 1.0, "make_plane with z = amplitude sin(2 pi f x / width) sin(2 pi f y / height).");
  m.def("make_icosphere", [](int s, double r) { return build(make_icosphere(s, r), false); },
        py::arg("subdivisions"), py::arg("radius") = 1.0, "Subdivided icosahedron on the sphere: 10*4^s+2 vertices.");
  m.def("make_disk", [](int rings, double r) { return build(make_disk(rings, r), false); }, py::arg("rings"),
        py::arg("radius") = 1.0, "Disk in z = 0: a centre vertex and `rings` rings of 6r vertices.");
  m.def("make_cylinder", [](int rings, int segments, double r, double h) { return build(make_cylinder(rings, segments, r, h), false); },
        py::arg("rings"), py::arg("segments"), py::arg("radius") = 1.0, py::arg("height") = 1.0,
        "Open cylinder around the z axis, z in [0, height].");
}

}  // namespace freeform::python
