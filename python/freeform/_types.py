"""The dicts EditSolver's frame methods return, as TypedDicts (for type checkers; at run time
they are plain dicts)."""
from typing import Optional, TypedDict


class FrameState(TypedDict):
    """The nonlinear model's state in what EditSolver.frame and settle return."""
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
    first_non_finite: Optional[int]
    folded_edges: int
    flipped_triangles: int
    overlaps: int
