// The compiled part of the Python package `freeform` (python/freeform/__init__.py re-exports it;
// docs/python.md).
#include "bindings.h"

PYBIND11_MODULE(_freeform, m) {
  using namespace freeform::python;
  m.doc() =
      "Real-time freeform mesh modeling (Botsch & Kobbelt 2004): read a mesh and an edit, precompute an "
      "EditSolver once, evaluate it per frame. See docs/python.md.";
  bind_errors(m);
  bind_mesh(m);
  bind_mesh_file(m);
  bind_edit(m);
  bind_solver(m);
}
