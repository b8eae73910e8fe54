"""Every error path: the exception type and the message (the C++ message for library errors,
the argument's name for wrong types and shapes)."""
import numpy as np
import pytest

import freeform
from conftest import plane_edit_dict, translation

TRIANGLE = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


def test_hierarchy():
    assert issubclass(freeform.Error, ValueError)
    assert issubclass(freeform.IoError, OSError) and issubclass(freeform.IoError, freeform.Error)
    assert issubclass(freeform.TopologyError, freeform.Error) and issubclass(freeform.SolverError, freeform.Error)


@pytest.mark.parametrize("vertices,faces,error,message", [
    (np.zeros((3, 2)), [[0, 1, 2]], ValueError, r"^vertices must have shape \(n, 3\), got \(3, 2\)$"),
    (np.zeros(9), [[0, 1, 2]], ValueError, r"^vertices must have shape \(n, 3\), got \(9,\)$"),
    (np.zeros((3, 3), complex), [[0, 1, 2]], TypeError, r"^vertices must be an array of real numbers, got dtype complex128$"),
    ("abc", [[0, 1, 2]], TypeError, r"^vertices must be an array of real numbers, got dtype <U3$"),
    (None, [[0, 1, 2]], TypeError, r"^vertices must be an array of real numbers, got dtype object$"),
    (TRIANGLE, [[0.0, 1.0, 2.0]], TypeError, r"^faces must be an array of integers, got dtype float64$"),
    (TRIANGLE, np.array([[True, False, True]]), TypeError, r"^faces must be an array of integers, got dtype bool$"),
    (TRIANGLE, [[0, 1, 2, 0]], ValueError, r"^faces must have shape \(m, 3\), got \(1, 4\)$"),
    (TRIANGLE, [[0, 1, 3]], freeform.Error, r"^face 0 references vertex 3, but the mesh has 3 vertices$"),
    (TRIANGLE, [[0, 1, -1]], freeform.Error, r"^face 0 references vertex -1, but the mesh has 3 vertices$"),
    (TRIANGLE, [[0, 1, 2**40]], freeform.Error, r"^faces: face 0 references vertex 1099511627776, which is out of range$"),
    ([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]], [[0, 1, 2]], freeform.Error, r"^vertex 1 has a non-finite coordinate$"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], [[0, 1, 2], [0, 1, 3], [0, 1, 3]], freeform.TopologyError, "repair"),
])
def test_mesh_arguments(vertices, faces, error, message):
    with pytest.raises(error, match=message):
        freeform.Mesh(vertices, faces)


def test_io_errors(tmp_path, plane):
    with pytest.raises(freeform.IoError, match=r"nothing\.off: cannot open for reading: No such file") as e:
        freeform.read_mesh(tmp_path / "nothing.off")
    assert isinstance(e.value, OSError)
    bad = tmp_path / "bad.off"
    bad.write_text("OFF\n3 1 0\n0 0 0\n1 0 0\n")
    with pytest.raises(freeform.IoError, match=r"bad\.off:4: unexpected end of file: header declares 3 vertices, found 2$"):
        freeform.read_mesh(bad)
    with pytest.raises(freeform.IoError, match=r"unknown mesh file extension"):
        freeform.read_mesh(tmp_path / "mesh.xyz")
    with pytest.raises(freeform.IoError, match=r"cannot create temporary file"):
        freeform.write_mesh(tmp_path / "missing" / "a.off", plane)
    with pytest.raises(freeform.Error, match=r"^cannot write mesh: face 0 has vertex index 5 out of range \(3 vertices\)$"):
        freeform.write_mesh(tmp_path / "a.off", TRIANGLE, [[0, 1, 5]])
    assert list(tmp_path.iterdir()) == [bad]  # nothing half-written
    with pytest.raises(TypeError, match="faces missing"):
        freeform.write_mesh(tmp_path / "a.off", TRIANGLE)
    with pytest.raises(TypeError, match=r"^path must be a str, bytes or os.PathLike, got <class 'int'>$"):
        freeform.read_mesh(5)


def test_edit_file_errors(tmp_path, plane):
    with pytest.raises(freeform.IoError, match=r"none\.json: cannot open for reading"):
        freeform.read_edit(tmp_path / "none.json", plane)
    bad = tmp_path / "bad.json"
    bad.write_text('{\n  "order": 2,\n  "support": }\n')
    with pytest.raises(freeform.IoError, match=r"bad\.json:3: malformed JSON at column 14"):
        freeform.read_edit(bad, plane)
    bad.write_text('{"support": {"vertices": [1]}, "support": {"vertices": [2]}}')
    with pytest.raises(freeform.Error, match=r'bad\.json: .*"support"'):
        freeform.read_edit(bad, plane)


def test_solver_errors(plane, plane_edit):
    other = freeform.make_plane(4, 4)
    message = r"^the edit was resolved on a mesh with 169 vertices, this mesh has 25$"
    with pytest.raises(freeform.Error, match=message):
        freeform.EditSolver(other, plane_edit)
    with pytest.raises(freeform.Error, match=message):
        freeform.deform(other, plane_edit)
    whole = freeform.Edit.from_dict({"support": {"vertices": list(range(plane.n_vertices))}}, plane)
    with pytest.raises(freeform.Error, match=r"^the support covers a whole component of the mesh"):
        freeform.EditSolver(plane, whole)
    with pytest.raises(TypeError):
        freeform.EditSolver(plane.vertices, plane_edit)


def test_transform_errors(solver):
    cases = [
        ([np.eye(4)] * 2, ValueError, r"^transforms has 2 entries, the solver has 1 movable handles"),
        ([], ValueError, r"^transforms has 0 entries"),
        (np.eye(4), ValueError, r"^transforms has 4 entries"),
        (np.zeros((2, 4, 4)), ValueError, r"^transforms must have shape \(1, 4, 4\) \(one matrix per movable handle\), got \(2, 4, 4\)$"),
        ([np.eye(3)], ValueError, r"^transforms\[0\] must have shape \(4, 4\), got \(3, 3\)$"),
        ([np.eye(4, dtype=complex)], TypeError, r"^transforms\[0\] must be an array of real numbers, got dtype complex128$"),
        (["abc"], TypeError, r"^transforms\[0\] must be an array of real numbers, got dtype <U3$"),
        (5, TypeError, r"^transforms must be a list of 4x4 arrays \(one per movable handle\), got <class 'int'>$"),
        ("abcd", TypeError, r"^transforms must be a list of 4x4 arrays"),
        ([np.ones((4, 4))], freeform.Error, r"^transforms\[0\]: the last row must be 0 0 0 1 \(an affine map\)$"),
        ([np.diag([np.inf, 1, 1, 1])], freeform.Error, r"^evaluate: transform 0 is not finite$"),
    ]
    for transforms, error, message in cases:
        for call in (lambda: solver.evaluate(transforms), lambda: solver.evaluate_into(solver.mesh.vertices, transforms)):
            with pytest.raises(error, match=message):
                call()
    with pytest.raises(ValueError, match=r"^n must be >= 1$"):
        solver._time_evaluate(0)


def test_out_errors(solver):
    n = solver.n_vertices
    t = [translation(0, 0, 0.1)]
    cases = [
        (np.zeros((n, 3), np.float32), TypeError, r"^out must be a float64 numpy array, got float32$"),
        (np.zeros((n, 3)).tolist(), TypeError, r"^out must be a float64 numpy array, got <class 'list'>$"),
        (np.zeros((n, 3), ">f8"), TypeError, r"^out must be a float64 numpy array, got >f8$"),
        (np.zeros((n, 4)), ValueError, rf"^out must have shape \({n}, 3\), got \({n}, 4\)$"),
        (np.zeros((n + 1, 3)), ValueError, rf"^out must have shape \({n}, 3\)"),
        (np.zeros(3 * n), ValueError, rf"^out must have shape \({n}, 3\), got \({3 * n},\)$"),
        (np.zeros((n, 6))[:, ::2], ValueError, r"^out must be C-contiguous and writeable"),
        (np.asfortranarray(np.zeros((n, 3))), ValueError, r"^out must be C-contiguous and writeable"),
    ]
    readonly = np.zeros((n, 3))
    readonly.flags.writeable = False
    cases.append((readonly, ValueError, r"^out must be C-contiguous and writeable"))
    for out, error, message in cases:
        before = np.array(out, copy=True)
        with pytest.raises(error, match=message):
            solver.evaluate_into(out, t)
        assert np.array_equal(np.asarray(out), before)  # untouched


def test_hostile_edit_dicts(tmp_path, plane):
    """Structures no edit has are refused with the reason, never a crash (issue: a list nested
    100,000 deep killed the interpreter)."""
    deep = [0]
    for _ in range(100_000):
        deep = [deep]
    with pytest.raises(freeform.Error, match=r"^edit: nested too deeply \(more than 1000 levels\) at \"support\.vertices\[0\]"):
        freeform.Edit.from_dict({"support": {"vertices": deep}}, plane)
    loop = [1]
    loop.append(loop)
    with pytest.raises(freeform.Error, match=r"nested too deeply"):
        freeform.Edit.from_dict({"support": {"vertices": loop}}, plane)
    with pytest.raises(freeform.Error, match=r"^edit: key '\\ud800' is not valid Unicode \(a lone surrogate\?\) at \"support\"$"):
        freeform.Edit.from_dict({"support": {"\ud800": 1}}, plane)
    with pytest.raises(freeform.Error, match=r"^edit: string '\\udfff' is not valid Unicode"):
        freeform.Edit.from_dict({"deformation": "\udfff", "support": {"vertices": [1]}}, plane)
    (tmp_path / "plane.sel").write_text("1\n" * plane.n_vertices)
    with pytest.raises(freeform.Error, match=r'"support\.sel" contains a NUL byte'):
        freeform.Edit.from_dict({"support": {"sel": str(tmp_path / "plane.sel") + "\0.junk", "labels": [1]}}, plane)


def test_writers_never_write_what_readers_refuse(tmp_path):
    bad = np.array(TRIANGLE, float)
    bad[1, 2] = np.nan
    with pytest.raises(freeform.Error, match=r"a\.off: cannot write vertex 1: its coordinate nan is not finite$"):
        freeform.write_mesh(tmp_path / "a.off", bad, [[0, 1, 2]])
    bad[1, 2] = 1e39
    with pytest.raises(freeform.Error, match=r"beyond the single precision of STL"):
        freeform.write_mesh(tmp_path / "a.stl", bad, [[0, 1, 2]])
    assert list(tmp_path.iterdir()) == []


def test_nonlinear_refuses_scales_it_would_blow_up():
    """A one-vertex handle scaled 1e6 about itself moves nothing in linear BCM; the nonlinear
    model spreads the scale to its neighbours (it moved one by 1,944 units, exit 0): refused."""
    mesh = freeform.make_icosphere(2, 1.0)
    faces = mesh.faces
    nb = int(next(x for x in faces[np.any(faces == 0, axis=1)].ravel() if x != 0))
    c = mesh.vertices[nb]

    def scaled(s):
        m = np.eye(4)
        m[:3, :3] *= s
        m[:3, 3] = c - s * c
        return m

    edit = {"support": {"vertices": [0, nb]}, "handles": [{"region": {"vertices": [nb]}}],
            "deformation": "nonlinear", "allow_unanchored": True}
    solver = freeform.EditSolver(mesh, freeform.Edit.from_dict(edit, mesh))
    for s, text in [(1e6, r"1000000"), (1e-4, r"0\.0001"), (1e200, r"1e\+200")]:
        with pytest.raises(freeform.Error, match=r"^evaluate: transform 0 scales by " + text + r"; the nonlinear model"):
            solver.evaluate([scaled(s)])
    assert np.isfinite(solver.evaluate([scaled(500.0)])).all()
    linear = freeform.EditSolver(mesh, freeform.Edit.from_dict(dict(edit, deformation="linear"), mesh))
    np.testing.assert_allclose(linear.evaluate([scaled(1e6)]), mesh.vertices, atol=1e-9)


def test_evaluate_never_returns_non_finite_positions(plane):
    """Finite transforms whose products overflow: evaluate raises like deform, and problems()
    names the first bad vertex of the frame."""
    for model in ("linear", "nonlinear"):
        d = plane_edit_dict()
        d["deformation"] = model
        solver = freeform.EditSolver(plane, freeform.Edit.from_dict(d, plane))
        huge = np.diag([1e200, 1e200, 1e200, 1.0])
        for call in (lambda: solver.evaluate([huge]), lambda: solver.evaluate_into(plane.vertices.copy(), [huge])):
            with pytest.raises(freeform.Error, match=r"non-finite positions|scales by 1e\+200"):
                call()
        if model == "linear":
            assert solver.problems()["non_finite"] > 0 and solver.problems()["first_non_finite"] is not None


def _interrupt_after(seconds):
    """Sends this process SIGINT (Ctrl-C) after `seconds`, from another thread."""
    import os
    import signal
    import threading
    timer = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


def test_ctrl_c_stops_a_long_nonlinear_solve():
    """A legal edit that would iterate for minutes (no tolerance reachable): Ctrl-C stops the
    constructor's first frame, evaluate, evaluate_into and settle within a fraction of a second
    (it used to run on: the solve never looked at Python's signals)."""
    import time
    # A tube (5.8k vertices) whose end is scaled 1.4 and turned 150 degrees: at k = 3 the iteration
    # keeps oscillating (step 0.005 after 3,000 iterations, 2.5 ms each). (The 744-vertex tube this
    # test used converges in 44 iterations since the membrane term, docs/nonlinear.md.)
    mesh = freeform.make_cylinder(120, 48, 0.2, 1.0)
    top = mesh.vertices[np.argmax(mesh.vertices[:, 2])].tolist()
    diag = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    d = {"order": 3, "support": {"sphere": {"center": top, "radius": 0.6 * diag}},
         "handles": [{"region": {"sphere": {"center": top, "radius": 0.15 * diag}}}],
         "deformation": "nonlinear", "allow_unanchored": True,
         "nonlinear": {"max_iterations": 100000, "tolerance": 1e-300}}
    solver = freeform.EditSolver(mesh, freeform.Edit.from_dict(d, mesh))  # identity: at rest at once
    turn = {"scale": [1.4, 1.4, 1.4], "rotate": {"axis": [0, 1, 0], "degrees": 150}}
    d["handles"][0]["transform"] = turn
    edit = freeform.Edit.from_dict(d, mesh)
    a = np.radians(150)
    turned = np.eye(4)
    turned[:3, :3] = 1.4 * np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    handle = mesh.vertices[np.linalg.norm(mesh.vertices - top, axis=1) <= 0.15 * diag]
    pivot = handle.mean(axis=0)  # the manipulator's default pivot: the handle's centroid
    turned[:3, 3] = pivot - turned[:3, :3] @ pivot
    out = mesh.vertices.copy()
    calls = [lambda: freeform.EditSolver(mesh, edit),
             lambda: solver.evaluate([turned]),
             lambda: solver.evaluate_into(out, [turned]),
             lambda: solver.settle(out, [turned])]
    for call in calls:
        timer = _interrupt_after(0.3)
        start = time.monotonic()
        with pytest.raises(KeyboardInterrupt):
            call()
        timer.join()
        assert time.monotonic() - start < 3.0
    assert np.array_equal(out, mesh.vertices)  # interrupted frames wrote nothing
