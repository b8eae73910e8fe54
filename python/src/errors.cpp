// The exceptions: freeform.Error (a ValueError) for everything the library refuses, with the
// subclasses IoError (also an OSError), TopologyError and SolverError; the C++ message as is.
#include "bindings.h"

#include "freeform/common/error.h"

namespace freeform::python {
namespace {

PyObject* new_exception(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  const std::string full = std::string("freeform.") + name;
  PyObject* type = PyErr_NewExceptionWithDoc(full.c_str(), doc, bases, nullptr);
  if (!type) throw py::error_already_set();
  m.attr(name) = py::handle(type);  // the module keeps a reference; this one lives as long
  return type;
}

}  // namespace

void bind_errors(py::module_& m) {
  static PyObject* error = new_exception(m, "Error", PyExc_ValueError,
                                         "Input the library refuses (mesh, edit, regions, arguments); a ValueError.");
  const py::tuple io_bases = py::make_tuple(py::handle(error), py::handle(PyExc_OSError));
  static PyObject* io_error = new_exception(m, "IoError", io_bases.ptr(),
                                            "A file could not be read or written: 'file:line: message'; an OSError.");
  static PyObject* topology_error =
      new_exception(m, "TopologyError", error, "Connectivity a halfedge mesh cannot represent (non-manifold).");
  static PyObject* solver_error =
      new_exception(m, "SolverError", error, "A linear solve failed, or a frame has non-finite positions.");

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const IoError& e) {
      PyErr_SetString(io_error, e.what());
    } catch (const TopologyError& e) {
      PyErr_SetString(topology_error, e.what());
    } catch (const SolverError& e) {
      PyErr_SetString(solver_error, e.what());
    } catch (const OutOfMemory& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());  // an address-space limit, not the input
    } catch (const InternalError& e) {
      PyErr_SetString(PyExc_RuntimeError, e.what());  // a bug in the library
    } catch (const Error& e) {
      PyErr_SetString(error, e.what());
    }
  });
}

}  // namespace freeform::python
