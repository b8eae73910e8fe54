"""A drag as an editor does it: frames that never wait for the nonlinear model, then settle.

    python3 examples/drag.py
"""
import numpy as np
from numpy.typing import NDArray

import freeform


def turn_about_x(degrees: float, pivot: NDArray[np.float64]) -> NDArray[np.float64]:
    a = np.radians(degrees)
    m = np.eye(4)
    m[1:3, 1:3] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    m[:3, 3] = pivot - m[:3, :3] @ pivot
    return m


bar = freeform.make_cylinder(40, 24, radius=0.1, height=1.0)
z = bar.vertices[:, 2]
edit = freeform.Edit.from_dict({
    "order": 2, "deformation": "nonlinear",
    "support": {"vertices": np.flatnonzero(z > 0.1)},
    "handles": [{"region": {"vertices": np.flatnonzero(z > 0.9)}}],
}, bar)
solver = freeform.EditSolver(bar, edit)
out = bar.vertices  # the rows a frame does not write keep these
pivot = np.array([0.0, 0.0, 0.1])  # the bar bends about the fixed part's edge
for step in range(1, 31):  # the mouse moves: 3 degrees a frame
    solver.frame(out, [turn_about_x(3.0 * step, pivot)])  # shows the newest iterate, at once
end = solver.settle(out, [turn_about_x(90.0, pivot)])  # the mouse stops
print(f"settled after {end['iterations']} iterations, converged {end['converged']}, "
      f"tip at y = {out[np.argmax(z), 1]:.3f}")
