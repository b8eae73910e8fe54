# Type stub of the freeform package (the compiled module freeform._freeform, re-exported).
# tests/python/test_package.py fails when a public name of the module has no entry here.
import os
from typing import Any, Callable, Sequence, TypedDict, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

_Path = Union[str, bytes, os.PathLike[str], os.PathLike[bytes]]
# One 4 x 4 affine matrix per movable handle: a sequence of (4, 4) arrays or one (m, 4, 4) array.
_Transforms = Union[Sequence[ArrayLike], ArrayLike, None]

class Error(ValueError):
    """Input the library refuses (mesh, edit, regions, arguments); a ValueError."""

class IoError(Error, OSError):
    """A file could not be read or written: 'file:line: message'; an OSError."""

class TopologyError(Error):
    """Connectivity a halfedge mesh cannot represent (non-manifold)."""

class SolverError(Error):
    """A linear solve failed, or a frame has non-finite positions."""

class Mesh:
    """A 2-manifold, consistently oriented triangle mesh with float64 positions."""
    def __init__(self, vertices: ArrayLike, faces: ArrayLike, *, repair: bool = False) -> None: ...
    @property
    def vertices(self) -> NDArray[np.float64]:
        """(n, 3) float64: a new copy of the positions."""
    @property
    def faces(self) -> NDArray[np.int64]:
        """(m, 3) int64: a new copy of the triangles."""
    @property
    def n_vertices(self) -> int: ...
    @property
    def n_faces(self) -> int: ...
    @property
    def n_edges(self) -> int: ...

class Edit:
    """An edit (support, handles with transforms, settings) resolved against a mesh."""
    @staticmethod
    def from_dict(d: dict[str, Any], mesh: Mesh, *, name: str = "edit", base_dir: _Path | None = None) -> Edit: ...
    def to_dict(self) -> dict[str, Any]: ...
    @property
    def order(self) -> int: ...
    @property
    def multiresolution(self) -> bool: ...
    @property
    def support(self) -> NDArray[np.int64]:
        """(s,) int64: the support's vertex indices."""
    @property
    def n_handles(self) -> int: ...
    @property
    def n_movable(self) -> int: ...

class FrameState(TypedDict):
    """What EditSolver.evaluate_within and refine return."""
    iterations: int
    residual: float
    converged: bool

class DragFrame(FrameState):
    """What EditSolver.frame and settle return."""
    written: bool
    predicted: bool
    settled: bool

class Problems(TypedDict):
    """What EditSolver.problems returns."""
    ok: bool
    non_finite: int
    first_non_finite: int | None
    folded_edges: int
    flipped_triangles: int
    overlaps: int

class EditSolver:
    """The precomputed edit: the constructor does all sparse work once, evaluate is the per-frame product."""
    def __init__(self, mesh: Mesh, edit: Edit, progress: Callable[[str, float], object] | None = None) -> None: ...
    def evaluate(self, transforms: _Transforms = None) -> NDArray[np.float64]:
        """(n, 3) float64: the positions of all vertices for these transforms."""
    def evaluate_into(self, out: NDArray[np.float64], transforms: _Transforms = None) -> None:
        """Writes the rows of `touched` into out ((n, 3) float64, C-contiguous)."""
    def evaluate_within(self, out: NDArray[np.float64], transforms: _Transforms = None, *,
                        budget_ms: float = 20.0) -> FrameState: ...
    def refine(self, out: NDArray[np.float64], transforms: _Transforms = None, *, budget_ms: float = 20.0) -> FrameState: ...
    def frame(self, out: NDArray[np.float64], transforms: _Transforms = None) -> DragFrame: ...
    def settle(self, out: NDArray[np.float64], transforms: _Transforms = None) -> DragFrame: ...
    def _time_evaluate(self, n: int, transforms: _Transforms = None, copy: bool = False) -> NDArray[np.float64]: ...
    @property
    def stats(self) -> dict[str, Any]: ...
    def problems(self) -> Problems: ...
    @property
    def mesh(self) -> Mesh: ...
    @property
    def n_vertices(self) -> int: ...
    @property
    def n_movable(self) -> int: ...
    @property
    def touched(self) -> NDArray[np.int64]:
        """(t,) int64: the vertices a frame writes, sorted."""
    @property
    def transforms(self) -> list[NDArray[np.float64]]:
        """The edit's own transforms: one (4, 4) float64 array per movable handle."""
    def handle_centroid(self, movable: int) -> NDArray[np.float64]:
        """(3,) float64: the rest centroid of movable handle `movable`."""

def read_mesh(path: _Path, *, repair: bool = False) -> Mesh: ...
def write_mesh(path: _Path, vertices: ArrayLike | Mesh, faces: ArrayLike | None = None, *, binary: bool = True) -> None: ...
def read_edit(path: _Path, mesh: Mesh) -> Edit: ...
def write_edit(path: _Path, edit: Edit) -> None: ...
def deform(mesh: Mesh, edit: Edit) -> NDArray[np.float64]: ...
def make_plane(nx: int, ny: int, width: float = 1.0, height: float = 1.0) -> Mesh: ...
def make_bumpy_plane(nx: int, ny: int, amplitude: float, frequency: float, width: float = 1.0,
                     height: float = 1.0) -> Mesh: ...
def make_icosphere(subdivisions: int, radius: float = 1.0) -> Mesh: ...
def make_disk(rings: int, radius: float = 1.0) -> Mesh: ...
def make_cylinder(rings: int, segments: int, radius: float = 1.0, height: float = 1.0) -> Mesh: ...
