"""Real-time freeform mesh modeling (Botsch & Kobbelt 2004): read a mesh and an edit, precompute an
EditSolver once, evaluate it per frame from numpy. docs/python.md.

The compiled module is ``freeform._freeform``; everything public is re-exported here, and the
type stub ``__init__.pyi`` describes it (PEP 561, ``py.typed``)."""
from ._freeform import (DEFORMATIONS, Edit, EditSolver, Error, IoError, Mesh, MeshFile, SolverError, TopologyError, deform,
                        make_bumpy_plane, make_cylinder, make_disk, make_icosphere, make_plane, read_edit, read_mesh,
                        read_mesh_file, write_edit, write_mesh, write_mesh_file)

from ._types import DragFrame, FrameState, Problems

__version__ = "0.1.0"
__all__ = ["DEFORMATIONS", "DragFrame", "Edit", "EditSolver", "Error", "FrameState", "IoError", "Mesh", "MeshFile", "Problems",
           "SolverError", "TopologyError", "deform", "make_bumpy_plane", "make_cylinder", "make_disk", "make_icosphere",
           "make_plane", "read_edit", "read_mesh", "read_mesh_file", "write_edit", "write_mesh", "write_mesh_file"]

for _cls in (Edit, EditSolver, Mesh, MeshFile):
    _cls.__module__ = __name__  # freeform.Mesh, not freeform._freeform.Mesh, in reprs and help()
del _cls
