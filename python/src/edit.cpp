// freeform.Edit: an edit file's content resolved against a mesh (docs/edit-format.md), read from
// a file or a dict with the same schema and messages, and back to a dict or a file.
#include "bindings.h"

#include "freeform/edit/edit_json.h"

namespace freeform::python {

void bind_edit(py::module_& m) {
  py::class_<PyEdit>(m, "Edit",
                     "An edit (support, handles with transforms, settings) resolved against a mesh: selectors are "
                     "vertex lists. Build with read_edit or Edit.from_dict.")
      .def_static(
          "from_dict",
          [](py::handle d, const Mesh& mesh, const std::string& name, py::handle base_dir) {
            const Json j = to_json(d, name);
            const std::string base = base_dir.is_none() ? std::string() : to_path(base_dir, "base_dir");
            py::gil_scoped_release release;  // geodesic selectors run Dijkstra
            return PyEdit{parse_edit(j, mesh, name, base), mesh.n_vertices()};
          },
          py::arg("d"), py::arg("mesh"), py::kw_only(), py::arg("name") = "edit", py::arg("base_dir") = py::none(),
          "The edit-file schema as Python data (numpy arrays and scalars allowed). Errors are freeform.Error with "
          "the edit file's messages, `name` in place of the file name; \"sel\" paths are relative to base_dir "
          "(default: the current folder).")
      .def("to_dict", [](const PyEdit& self) { return to_python(edit_to_json(self.edit)); },
           "The edit as edit-file data: vertex-list selectors, explicit settings, \"matrix\" transforms at full "
           "precision; Edit.from_dict(e.to_dict(), mesh) deforms bit for bit like e.")
      .def_property_readonly("order", [](const PyEdit& self) { return self.edit.settings.order; },
                             "The stiffness k (1, 2 or 3): the order of the k-harmonic energy.")
      .def_property_readonly("multiresolution", [](const PyEdit& self) { return self.edit.multiresolution; },
                             "Whether the detail is kept on a smooth base (docs/multires.md).")
      .def_property_readonly("support", [](const PyEdit& self) { return vertex_array(self.edit.support); },
                             "(s,) int64 array: the support's vertex indices.")
      .def_property_readonly("n_handles", [](const PyEdit& self) { return self.edit.handles.size(); },
                             "Handles, movable and fixed.")
      .def_property_readonly("n_movable", [](const PyEdit& self) { return n_movable(self.edit); },
                             "Movable handles: the number of transforms per frame.")
      .def("__repr__", [](const PyEdit& self) {
        return "<freeform.Edit order " + std::to_string(self.edit.settings.order) + ", " +
               std::to_string(self.edit.support.size()) + " support vertices, " +
               std::to_string(self.edit.handles.size()) + " handles>";
      });

  m.def(
      "read_edit",
      [](py::handle path, const Mesh& mesh) {
        const std::string p = to_path(path);
        py::gil_scoped_release release;
        return PyEdit{read_edit_file(p, mesh), mesh.n_vertices()};
      },
      py::arg("path"), py::arg("mesh"),
      "Reads an edit file (docs/edit-format.md) and resolves its selectors on `mesh`. Raises Error "
      "'FILE: what is wrong at KEY.PATH' or IoError.");
  m.def(
      "write_edit",
      [](py::handle path, const PyEdit& edit) {
        const std::string p = to_path(path);
        py::gil_scoped_release release;
        write_edit_file(p, edit.edit);
      },
      py::arg("path"), py::arg("edit"), "Writes Edit.to_dict()'s content as an edit file, atomically.");
  py::tuple names(kDeformations.size());  // the models' edit-file names: front ends list these
  for (std::size_t i = 0; i < kDeformations.size(); ++i) names[i] = std::string(deformation_name(kDeformations[i]));
  m.attr("DEFORMATIONS") = names;
}

}  // namespace freeform::python
