"""EditSolver: evaluate / evaluate_into, transforms, progress and cancellation, lifetimes,
threads, reference counts and memory over many frames."""
import gc
import subprocess
import sys
import threading
import tracemalloc

import numpy as np
import pytest

import freeform
from conftest import plane_edit_dict, translation


def test_default_frame_is_deform(plane, plane_edit, solver):
    expected = freeform.deform(plane, plane_edit)
    assert np.array_equal(solver.evaluate(), expected)
    assert np.array_equal(solver.evaluate(solver.transforms), expected)
    assert np.isfinite(expected).all() and not np.array_equal(expected, plane.vertices)


def test_identity_reproduces_the_rest_shape(plane, solver):
    assert np.allclose(solver.evaluate([np.eye(4)]), plane.vertices, rtol=0, atol=1e-12)


def test_solver_properties(plane, solver):
    assert (solver.n_vertices, solver.n_movable) == (plane.n_vertices, 1)
    assert len(solver.transforms) == 1 and solver.transforms[0].shape == (4, 4)
    touched = solver.touched
    assert touched.dtype == np.int64 and np.all(np.diff(touched) > 0) and 80 not in touched
    assert np.allclose(solver.handle_centroid(0), [0.5, 0.5, 0.0])
    with pytest.raises(IndexError, match="movable handle 1 out of range"):
        solver.handle_centroid(1)
    assert solver.mesh.n_vertices == plane.n_vertices
    seconds = solver._time_evaluate(3, copy=True)  # the benchmark's C++ reference
    assert seconds.shape == (3,) and (seconds > 0).all()


def test_transform_forms_agree(solver):
    m = translation(0.1, -0.2, 0.3)
    m[:3, :3] = [[0.9, 0.1, 0], [-0.1, 0.9, 0], [0, 0, 1.1]]
    expected = solver.evaluate([m])
    strided = np.zeros((4, 8))
    strided[:, ::2] = m
    for t in ([m], (m,), m[None], [m.tolist()], [np.asfortranarray(m)], [strided[:, ::2]], [m.astype(">f8")]):
        assert np.array_equal(solver.evaluate(t), expected)
    m32 = m.astype(np.float32)
    assert np.array_equal(solver.evaluate([m32]), solver.evaluate([m32.astype(np.float64)]))


def test_evaluate_into_writes_the_touched_rows(plane, solver):
    t = [translation(0, 0, -0.3)]
    out = plane.vertices
    assert solver.evaluate_into(out, t) is None
    assert np.array_equal(out, solver.evaluate(t))
    marked = np.full((plane.n_vertices, 3), np.nan)
    solver.evaluate_into(marked, t)
    written = np.flatnonzero(np.isfinite(marked).all(axis=1))
    assert np.array_equal(written, solver.touched)


def test_stats_and_problems(solver):
    stats = solver.stats
    assert stats["vertices"] == 169 and stats["faces"] == 288 and stats["order"] == 2
    assert stats["counts"]["handles"] == [{"vertices": 5, "movable": True}, {"vertices": 1, "movable": False}]
    assert stats["counts"]["free"] + stats["counts"]["fixed"] + 6 == 169
    assert stats["timings_ms"]["evaluate"] >= 0 and stats["multiresolution"]["normal_encoded"] >= 0
    # A small support: refinement against the unassembled operator converges at once.
    assert stats["refinement"]["converged"] is True and stats["refinement"]["steps"] >= 1
    assert 0 <= stats["forward_error"] < 1e-12
    assert solver.problems() == {"ok": True, "non_finite": 0, "first_non_finite": None, "folded_edges": 0,
                                 "flipped_triangles": 0, "overlaps": 0}
    assert stats["warnings"] == [] and stats["precompute"]["wall_ms"] > 0
    assert [p["name"] for p in stats["precompute"]["phases"]][-4:] == ["factorization", "basis", "refinement",
                                                                       "model_setup"]
    solver.evaluate([translation(0, 0, 2.0)])  # pulled far out of the plane: the frame folds
    assert solver.problems()["folded_edges"] > 0 and solver.stats["folded_edges"] > 0
    # The same sentences `freeform deform` prints (edit_warnings).
    assert any("folded edges" in w for w in solver.stats["warnings"])


def test_progress_reports_stages(plane, plane_edit):
    seen = []
    freeform.EditSolver(plane, plane_edit, progress=lambda stage, fraction: seen.append((stage, fraction)))
    stages = [s for s, _ in seen]
    fractions = [f for _, f in seen]
    assert {"assembly", "factorization", "basis"} <= set(stages)
    assert fractions == sorted(fractions) and 0 <= fractions[0] and fractions[-1] <= 1


class Stop(Exception):
    pass


def test_raising_from_progress_cancels(plane, plane_edit):
    calls = []

    def progress(stage, fraction):
        calls.append(stage)
        if stage == "factorization":
            raise Stop("user pressed cancel")

    with pytest.raises(Stop, match="user pressed cancel"):
        freeform.EditSolver(plane, plane_edit, progress=progress)
    assert calls[-1] == "factorization"  # nothing was reported after the exception
    with pytest.raises(TypeError):
        freeform.EditSolver(plane, plane_edit, progress=lambda: None)  # wrong signature: its TypeError
    with pytest.raises(TypeError, match=r"^progress must be None or a callable \(stage, fraction\), got <class 'int'>$"):
        freeform.EditSolver(plane, plane_edit, progress=5)


def test_solver_keeps_its_mesh_alive():
    mesh = freeform.make_plane(12, 12)
    rest = mesh.vertices
    solver = freeform.EditSolver(mesh, freeform.Edit.from_dict(plane_edit_dict(), mesh))
    del mesh
    gc.collect()
    assert np.array_equal(solver.mesh.vertices, rest)
    frame = solver.evaluate()
    del solver
    gc.collect()
    assert np.isfinite(frame).all() and frame.flags.owndata  # arrays own their memory


def test_threads_share_a_solver(solver):
    shifts = [translation(0, 0, 0.05 * i) for i in range(4)]
    expected = [solver.evaluate([t]) for t in shifts]
    errors = []

    def run(i):
        out = solver.mesh.vertices
        for _ in range(100):
            solver.evaluate_into(out, [shifts[i]])
            if not np.array_equal(out, expected[i]) or not np.array_equal(solver.evaluate([shifts[i]]), expected[i]):
                errors.append(i)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors


def test_reference_counts_and_memory_stable_over_10000_frames(plane, solver):
    out = plane.vertices
    m = translation(0, 0, 0.1)
    transforms = [m]
    stacked = m[None].copy()
    for _ in range(100):  # warm up caches (numpy, pybind11 type info)
        solver.evaluate_into(out, transforms)
        solver.evaluate(stacked)
    gc.collect()
    objects = (out, m, transforms, stacked, solver, None)
    before = [sys.getrefcount(o) for o in objects]
    tracemalloc.start()
    start, _ = tracemalloc.get_traced_memory()
    for i in range(10_000):
        solver.evaluate_into(out, transforms)
        frame = solver.evaluate(stacked if i % 2 else None)
    del frame
    gc.collect()
    end, _ = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert [sys.getrefcount(o) for o in objects] == before
    assert end - start < 16 * 1024, f"{end - start} bytes more after 10,000 frames"


def test_dev_mode_subprocess(tmp_path):
    """A short session under python -X dev: errors, frames, garbage collection, clean exit."""
    script = """
import gc, numpy as np, freeform
mesh = freeform.make_plane(6, 6)
edit = freeform.Edit.from_dict({"support": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.4}},
    "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0], "radius": 0.1}}}]}, mesh)
solver = freeform.EditSolver(mesh, edit, progress=lambda s, f: None)
out = mesh.vertices
for bad in ([np.eye(3)], [np.eye(4)] * 2, "x", [np.full((4, 4), np.nan)]):
    try:
        solver.evaluate_into(out, bad)
    except (TypeError, ValueError):
        pass
for _ in range(100):
    solver.evaluate_into(out, [np.eye(4)])
del mesh, edit
gc.collect()
print(solver.evaluate().shape)
"""
    run = subprocess.run([sys.executable, "-X", "dev", "-W", "error", "-c", script], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "(49, 3)" and run.stderr == ""


def test_nonlinear_model_reports_its_iterations(plane):
    d = plane_edit_dict()
    d["deformation"] = "nonlinear"
    d["nonlinear"] = {"max_iterations": 50, "tolerance": 1e-6}
    edit = freeform.Edit.from_dict(d, plane)
    assert edit.to_dict()["deformation"] == "nonlinear"
    solver = freeform.EditSolver(plane, edit)
    out = solver.evaluate()
    assert np.isfinite(out).all()
    stats = solver.stats
    assert stats["deformation"] == "nonlinear"
    assert stats["nonlinear"]["converged"] is True
    assert 1 <= stats["nonlinear"]["iterations"] <= 50
    assert np.array_equal(out, freeform.deform(plane, edit))  # a cold solve is deterministic
    linear = freeform.EditSolver(plane, freeform.Edit.from_dict(plane_edit_dict(), plane))
    assert linear.stats["nonlinear"] is None


def test_nonlinear_keeps_the_volume_of_closed_meshes():
    """A sphere's cap pulled up and turned 90 degrees: with the volume term (the default) the
    enclosed volume, computed here from the faces, stays the rest volume; without it, it
    changes."""
    sphere = freeform.make_icosphere(3)
    v, f = sphere.vertices, np.asarray(sphere.faces)
    support = np.nonzero(v[:, 2] > -0.2)[0].tolist()
    cap = np.nonzero(v[:, 2] > 0.8)[0].tolist()
    c, s = np.cos(np.pi / 2), np.sin(np.pi / 2)
    t = np.eye(4)
    t[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]
    t[:3, 3] = [0, -0.9, 1.2]

    def volume(x):
        return np.einsum("ij,ij->i", x[f[:, 0]], np.cross(x[f[:, 1]], x[f[:, 2]])).sum() / 6.0

    def run(preserve):
        d = {"order": 2, "multiresolution": False, "deformation": "nonlinear",
             "nonlinear": {"preserve_volume": preserve}, "support": {"vertices": support},
             "handles": [{"region": {"vertices": cap}, "transform": {"matrix": t.tolist()}}]}
        edit = freeform.Edit.from_dict(d, sphere)
        assert edit.to_dict()["nonlinear"]["preserve_volume"] is preserve
        return freeform.deform(sphere, edit)

    rest = volume(v)
    assert abs(volume(run(True)) / rest - 1.0) < 1e-6
    assert abs(volume(run(False)) / rest - 1.0) > 0.01


def test_frames_never_wait_and_settle_on_the_models_solution(plane):
    """frame(): the worker thread iterates while each call returns its newest iterate (handle
    exact); settle() waits for the converged shape, which is the cold solve's fixed point."""
    d = plane_edit_dict()
    d["deformation"] = "nonlinear"
    d["nonlinear"] = {"tolerance": 1e-7}
    solver = freeform.EditSolver(plane, freeform.Edit.from_dict(d, plane))
    out = plane.vertices
    pivot = solver.handle_centroid(0)
    rest = plane.vertices.copy()
    handle = np.linalg.norm(rest - [0.5, 0.5, 0.0], axis=1) < 0.085  # inside the handle's sphere
    assert handle.sum() >= 5
    for angle in np.radians(np.arange(6, 96, 6)):
        c, s = np.cos(angle), np.sin(angle)
        t = np.eye(4)
        t[:3, :3] = [[1, 0, 0], [0, c, -s], [0, s, c]]
        t[:3, 3] = pivot - t[:3, :3] @ pivot + [0, 0, 0.2]
        state = solver.frame(out, [t])
        # New transforms: the worker cannot be there yet, so (after the first, which waits for
        # the worker's start and may find it converged already) this is a prediction.
        assert state["written"] and np.isfinite(out).all()
        assert state["predicted"] == (angle > np.radians(7))
        assert not state["settled"] or not state["predicted"]
        moved = rest[handle] @ t[:3, :3].T + t[:3, 3]
        assert np.abs(out[handle] - moved).max() < 1e-12
    state = solver.settle(out, [t])
    assert state["settled"] and state["converged"] and state["iterations"] > 1
    assert solver.frame(out, [t])["written"] is False  # settled: nothing new
    assert solver.stats["nonlinear"]["converged"] is True
    handles = [dict(h) for h in d["handles"]]
    handles[0]["transform"] = {"matrix": t}
    cold = freeform.deform(plane, freeform.Edit.from_dict(dict(d, handles=handles), plane))
    assert np.abs(out - cold).max() < 1e-4
    lin = freeform.EditSolver(plane, freeform.Edit.from_dict(plane_edit_dict(), plane))
    assert lin.frame(out, None)["settled"] is True


def test_an_order_3_edit_beyond_double_precision_is_solved_at_order_2():
    """A grid with a strip of needles 1e-5 wide: its order-3 solve is far from the solution, so
    the edit is solved at order 2, which the stats say (as `freeform deform` does)."""
    rows = [float(y) for y in range(6)] + [5 + 1e-5] + [y + 1e-5 for y in range(6, 11)]
    vertices = np.array([(x, y, 0.0) for y in rows for x in range(11)])
    faces = []
    for r in range(len(rows) - 1):
        for x in range(10):
            a = r * 11 + x
            faces += [(a, a + 1, a + 12), (a, a + 12, a + 11)]
    mesh = freeform.Mesh(vertices, np.array(faces))
    edit = {"support": {"sphere": {"center": [5, 5, 0], "radius": 4.3}},
            "handles": [{"region": {"sphere": {"center": [5, 5, 0], "radius": 1.2}},
                         "transform": {"translate": [0, 0, 1]}}]}
    results = {}
    for order in (2, 3):
        solver = freeform.EditSolver(mesh, freeform.Edit.from_dict({**edit, "order": order}, mesh))
        results[order] = solver.evaluate()
        assert solver.stats["order"] == 2
        fallback = [w for w in solver.stats["warnings"] if "solved at order 2" in w]
        assert len(fallback) == (order == 3)
    assert "the order-3 solve's estimated error is" in fallback[0]
    assert np.array_equal(results[2], results[3]) and results[3][:, 2].max() == pytest.approx(1.0)
