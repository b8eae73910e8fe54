"""Shared fixtures of the Python module's tests (run by ctest: tests/python/CMakeLists.txt).

Environment (set by ctest): PYTHONPATH = build/<preset>/python, FREEFORM_CLI = the freeform
command, FREEFORM_MESH_DIR = the libcgal-demo meshes, FREEFORM_DATA_DIR = data/.
"""
import os
import pathlib

import numpy as np
import pytest

import freeform

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA_DIR = pathlib.Path(os.environ.get("FREEFORM_DATA_DIR", REPO / "data"))
MESH_DIR = pathlib.Path(os.environ.get("FREEFORM_MESH_DIR", REPO / ".cache" / "cgal-meshes"))


def require_file(path):
    """Skips (or fails with FREEFORM_REQUIRE_DATA=1) when a data file is missing."""
    path = pathlib.Path(path)
    if not path.exists():
        message = f"{path} missing; run scripts/fetch-data.sh"
        if os.environ.get("FREEFORM_REQUIRE_DATA") == "1":
            pytest.fail(message)
        pytest.skip(message)
    return path


@pytest.fixture(scope="session")
def cli():
    """The freeform command of the same build."""
    path = os.environ.get("FREEFORM_CLI")
    if not path:
        pytest.skip("FREEFORM_CLI not set (run through ctest)")
    return path


@pytest.fixture()
def plane():
    """A 12 x 12 grid on the unit square (169 vertices, 288 faces)."""
    return freeform.make_plane(12, 12)


def plane_edit_dict(order=2):
    """A disc support around the centre with a movable centre handle and an immovable one."""
    return {
        "order": order,
        "support": {"sphere": {"center": [0.5, 0.5, 0.0], "radius": 0.42}},
        "handles": [
            {"region": {"sphere": {"center": [0.5, 0.5, 0.0], "radius": 0.09}},
             "transform": {"translate": [0.0, 0.0, 0.2], "rotate": {"axis": [1, 0, 0], "degrees": 10}}},
            {"region": {"vertices": [6 * 13 + 2]}, "fixed": True},  # (1/6, 1/2): inside the support
        ],
    }


@pytest.fixture()
def plane_edit(plane):
    return freeform.Edit.from_dict(plane_edit_dict(), plane)


@pytest.fixture()
def solver(plane, plane_edit):
    return freeform.EditSolver(plane, plane_edit)


def translation(x, y, z):
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t
