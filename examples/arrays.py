"""(V, F) arrays in, (V, F) arrays out: an edit whose regions are numpy selections.

    python3 examples/arrays.py
"""
import numpy as np
from numpy.typing import NDArray

import freeform


def lift_the_top(V: NDArray[np.float64], F: NDArray[np.int64], height: float) -> NDArray[np.float64]:
    """Moves the top of a closed surface up by `height`; the support is a ball around the top."""
    mesh = freeform.Mesh(V, F)
    tip = V[np.argmax(V[:, 2])]
    d = np.linalg.norm(V - tip, axis=1)
    move = np.eye(4)
    move[2, 3] = height
    edit = freeform.Edit.from_dict({
        "order": 3,
        "support": {"vertices": np.flatnonzero(d < 0.9)},
        "handles": [{"region": {"vertices": np.flatnonzero(d < 0.2)}, "transform": {"matrix": move}}],
    }, mesh)
    return freeform.deform(mesh, edit)  # (n, 3) float64, same vertex order


sphere = freeform.make_icosphere(3)  # or trimesh's / libigl's / Open3D's (V, F)
V = lift_the_top(sphere.vertices, sphere.faces, 0.5)
print(f"top at z = {V[:, 2].max():.3f}, bottom at z = {V[:, 2].min():.3f}")
