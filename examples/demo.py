"""The README's main job from Python: bend the armadillo's ear with data/edits/armadillo.json.

    python3 examples/demo.py      # after scripts/fetch-data.sh; writes build/demo/armadillo-deformed-py.off
"""
import os
import pathlib

import freeform

REPO = pathlib.Path(__file__).resolve().parents[1]
meshes = pathlib.Path(os.environ.get("FREEFORM_MESH_DIR", REPO / ".cache" / "cgal-meshes"))
out = pathlib.Path(os.environ.get("FREEFORM_OUT_DIR", REPO / "build" / "demo"))
out.mkdir(parents=True, exist_ok=True)

mesh = freeform.read_mesh(meshes / "armadillo.off")
edit = freeform.read_edit(REPO / "data" / "edits" / "armadillo.json", mesh)
solver = freeform.EditSolver(mesh, edit, progress=lambda stage, done: print(f"{stage}: {done:.0%}"))
V = solver.evaluate()  # the edit's own transform: what `freeform deform` writes
freeform.write_mesh(out / "armadillo-deformed-py.off", V, mesh.faces)
stats = solver.stats
print(stats["counts"]["free"], "free vertices, factorization", stats["timings_ms"]["factorization"], "ms")
