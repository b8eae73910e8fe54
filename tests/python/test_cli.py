"""The module against the freeform command of the same build, on the demo edit (the armadillo's
ear, README.md): bit-for-bit equal positions for the edit's own transform and for a new matrix.
OFF keeps doubles exactly (shortest round-trip text), so the CLI's output is compared exactly."""
import json
import subprocess

import numpy as np
import pytest

import freeform
from conftest import DATA_DIR, MESH_DIR, require_file


@pytest.fixture(scope="module")
def demo():
    mesh = freeform.read_mesh(require_file(MESH_DIR / "armadillo.off"))
    edit = freeform.read_edit(DATA_DIR / "edits" / "armadillo.json", mesh)
    return mesh, edit, freeform.EditSolver(mesh, edit)


def run_cli(cli, tmp_path, edit_path):
    out, report = tmp_path / "out.off", tmp_path / "report.json"
    subprocess.run([cli, "deform", str(MESH_DIR / "armadillo.off"), "--edit", str(edit_path), "-o", str(out),
                    "--report", str(report)], check=True, capture_output=True, timeout=300)
    return freeform.read_mesh(out).vertices, json.loads(report.read_text())


def test_demo_deform_equals_the_cli(cli, tmp_path, demo):
    mesh, edit, solver = demo
    expected, report = run_cli(cli, tmp_path, DATA_DIR / "edits" / "armadillo.json")
    deformed = freeform.deform(mesh, edit)
    assert np.array_equal(deformed, expected)
    assert np.array_equal(solver.evaluate(), expected)
    out = mesh.vertices
    solver.evaluate_into(out)
    assert np.array_equal(out, expected)
    assert not np.array_equal(deformed, mesh.vertices)
    # solver.stats has the report's keys but the CLI's own (paths, repeats, memory)
    cli_only = {"input", "output", "edit", "evaluate_repeats", "peak_memory_mb"}
    assert list(solver.stats) == [k for k in report if k not in cli_only]
    assert solver.stats["counts"] == report["counts"]
    assert solver.stats["multiresolution"].keys() == report["multiresolution"].keys() - {"reconstruct_repeats"}


def test_new_matrix_equals_the_cli(cli, tmp_path, demo):
    mesh, edit, solver = demo
    a = np.radians(20.0)
    m = np.eye(4)
    m[:3, :3] = [[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]]
    c = solver.handle_centroid(0)
    m[:3, 3] = c - m[:3, :3] @ c + [1.0 / 3.0, 4.0, -2.5]
    d = json.loads((DATA_DIR / "edits" / "armadillo.json").read_text())
    d["handles"][0]["transform"] = {"matrix": m.tolist()}
    path = tmp_path / "matrix.json"
    path.write_text(json.dumps(d))  # repr of floats: exact
    expected, _ = run_cli(cli, tmp_path, path)
    assert np.array_equal(solver.evaluate([m]), expected)
    assert np.array_equal(freeform.deform(mesh, freeform.Edit.from_dict(d, mesh)), expected)


def test_nonlinear_model_carries_overhanging_detail(cli, tmp_path, demo):
    """The demo's ear overhangs its smooth base: with the nonlinear model, multiresolution leaves
    the detail to the model (docs/nonlinear.md), the same result as without the decomposition."""
    mesh = demo[0]
    d = json.loads((DATA_DIR / "edits" / "armadillo.json").read_text())
    d["deformation"] = "nonlinear"
    path = tmp_path / "nonlinear.json"
    path.write_text(json.dumps(d))
    carried, report = run_cli(cli, tmp_path, path)
    assert report["multiresolution"]["detail"] == "nonlinear_model"
    assert "overhangs its base" in report["multiresolution"]["operator_fallback"]
    assert report["nonlinear"]["converged"]
    d["multiresolution"] = False
    assert np.array_equal(freeform.deform(mesh, freeform.Edit.from_dict(d, mesh)), carried)
    d["deformation"] = "linear"
    d["multiresolution"] = True
    # The linear model decomposes it (normal displacement: overhanging detail has no vertex frames).
    assert freeform.EditSolver(mesh, freeform.Edit.from_dict(d, mesh)).stats["multiresolution"]["detail"] == (
        "normal_displacement")


def test_memory_caps_fail_cleanly(cli, tmp_path):
    """A k = 3 edit of a 150k-vertex plane under `ulimit -v`: a message and exit 1 within
    seconds at every cap, never a hang or a crash, and the old output intact. (OpenBLAS retried
    its 128 MB buffers forever at 200-400 MB, its shutdown hung after the message at 120 MB,
    and cholmod_solve crashed at 300 MB with one thread.)"""
    import os
    import resource
    if os.environ.get("FREEFORM_PYTHON_SANITIZED") == "1":
        pytest.skip("the sanitizers reserve terabytes of address space: no address-space limit fits")
    plane = tmp_path / "plane.off"
    freeform.write_mesh(plane, freeform.make_plane(386, 386))
    edit = tmp_path / "edit.json"
    edit.write_text(json.dumps({"order": 3, "support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.45}},
                                "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.05}},
                                             "transform": {"translate": [0, 0, 0.1]}}]}))
    out = tmp_path / "out.off"
    out.write_text("old output\n")
    for megabytes in (120, 300, 450, 700):
        for threads in ("1", "2"):
            limit = megabytes << 20
            result = subprocess.run(
                [cli, "deform", str(plane), "--edit", str(edit), "-o", str(out)], capture_output=True, text=True,
                timeout=60, env=dict(os.environ, OPENBLAS_NUM_THREADS=threads),
                preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (limit, limit)))
            case = f"{megabytes} MB, {threads} threads: {result.stderr}"
            assert result.returncode == 1, case
            assert result.stderr.startswith("freeform: error: out of memory"), case
            assert "ulimit -v" in result.stderr, case
            assert out.read_text() == "old output\n", case
    assert sorted(p.name for p in tmp_path.iterdir()) == ["edit.json", "out.off", "plane.off"]
