#!/usr/bin/env python3
"""Fuzz target of the Python module's entry points for untrusted data: Edit.from_dict and
Mesh(V, F), then EditSolver / evaluate on what they accept (docs/robustness.md).

    fuzz/fuzz_python_api.py [--seconds S | --cases N] [--seed SEED]

Random structures (nested dicts and lists with the edit vocabulary and junk: deep nesting,
self-containing lists, lone surrogates, NUL bytes, huge and non-finite numbers, numpy scalars
and arrays of every dtype and memory order) and random vertex / face arrays. Every call must
return or raise one of the exceptions the module documents (freeform.Error, TypeError,
ValueError, MemoryError, OverflowError); anything else is printed with the case's seed and
exits 1. A crash kills the process: run it from a parent that checks the signal
(scripts/run-fuzzers.sh python, scripts/hostile-sweep.py, tests/python/test_fuzz_python_api.py).
"""
import argparse
import random
import sys
import time
import warnings

import numpy as np

import freeform

ALLOWED = (freeform.Error, TypeError, ValueError, MemoryError, OverflowError)
KEYS = ["order", "support", "handles", "smoothness", "outer", "inner", "segments", "vertices", "sphere",
        "geodesic", "sel", "labels", "center", "radius", "region", "transform", "translate", "rotate",
        "axis", "degrees", "scale", "pivot", "matrix", "fixed", "deformation", "nonlinear", "max_iterations",
        "tolerance", "preserve_volume", "multiresolution", "anisotropic", "allow_unanchored", "value"]
STRINGS = ["linear", "nonlinear", "", "x", "a.sel\0.junk", "\ud800", "\udfff key", "\0", "é" * 3, "1e999"]
NUMBERS = [0, 1, 2, 3, -1, 0.5, 1e-300, 1e300, 1e308, float("nan"), float("inf"), -float("inf"), 2**63, 2**70,
           -2**63 - 1, 5e-324, 1e6, 1e-6]
DTYPES = [np.float64, np.float32, np.int32, np.int64, np.uint8, np.uint64, np.bool_, np.complex128, np.float16,
          object, "U3"]


def value(rng, depth):
    r = rng.random()
    if depth > 6 or r < 0.35:
        return rng.choice([rng.choice(NUMBERS), rng.choice(STRINGS), None, True, False,
                           np.float32(rng.choice(NUMBERS[:8])), np.int64(rng.randrange(-5, 200)),
                           np.bool_(rng.random() < 0.5), b"bytes", 1 + 2j, {1, 2}, object()])
    if r < 0.6:
        return {(rng.choice(KEYS) if rng.random() < 0.9 else rng.choice([1, None, "\ud800", "k\0"])): value(rng, depth + 1)
                for _ in range(rng.randrange(4))}
    if r < 0.85:
        out = [value(rng, depth + 1) for _ in range(rng.randrange(5))]
        if rng.random() < 0.05:
            out.append(out)  # contains itself
        return tuple(out) if rng.random() < 0.1 else out
    if r < 0.9:
        deep = [1]
        for _ in range(rng.choice([10, 999, 1001, 5000, 100000])):
            deep = [deep]
        return deep
    return array(rng, (rng.randrange(0, 5), rng.choice([3, 4, 1])))


def array(rng, shape):
    dtype = rng.choice(DTYPES)
    try:
        a = np.array(np.random.default_rng(rng.randrange(1 << 30)).normal(size=shape) * rng.choice([1, 1e300, 1e-300]))
        a = a.astype(dtype)
    except (TypeError, ValueError):
        a = np.zeros(shape)
    if rng.random() < 0.2 and a.ndim == 2:
        a = np.asfortranarray(a)
    if rng.random() < 0.1 and a.ndim == 2 and a.shape[0] > 1:
        a = a[::2]
    return a


def edit_dict(rng, n_vertices):
    """Mostly valid-looking edits with one or two random mutations."""
    d = {"support": {"sphere": {"center": [0.5, 0.5, 0.0], "radius": 0.4}},
         "handles": [{"region": {"sphere": {"center": [0.5, 0.5, 0.0], "radius": 0.1}},
                      "transform": {"translate": [0, 0, 0.2]}}]}
    if rng.random() < 0.3:
        d["deformation"] = "nonlinear"
    handle = d["handles"][0]
    targets = [d, d["support"], handle, handle["transform"], handle["region"]]
    for _ in range(rng.randrange(1, 3)):
        target = rng.choice(targets)
        key = rng.choice(KEYS)
        if rng.random() < 0.8:
            target[key] = value(rng, 1)
        else:
            target.pop(key, None)
    if rng.random() < 0.1:
        d["support"] = {"vertices": [rng.randrange(-2, n_vertices + 2) for _ in range(rng.randrange(5))]}
    return d


def mesh_case(rng):
    n = rng.randrange(0, 30)
    vertices = array(rng, (n, rng.choice([3, 3, 3, 2])))
    faces = np.array([[rng.randrange(-1, n + 1) for _ in range(3)] for _ in range(rng.randrange(0, 20))],
                     dtype=rng.choice([np.int64, np.int32, np.uint32, np.float64]))
    if rng.random() < 0.1:
        faces = faces.reshape(-1)
    return vertices, faces


def one_case(seed, plane):
    rng = random.Random(seed)
    try:
        if rng.random() < 0.6:
            edit = freeform.Edit.from_dict(edit_dict(rng, plane.n_vertices), plane)
            solver = freeform.EditSolver(plane, edit)
            solver.evaluate([np.eye(4) * rng.choice([1, 1e3, 1e200, -1]) + np.diag([0, 0, 0, 1])] * solver.n_movable)
            solver.problems()
        else:
            vertices, faces = mesh_case(rng)
            mesh = freeform.Mesh(vertices, faces)
            mesh.vertices, mesh.faces
    except ALLOWED:
        pass
    except Exception as e:  # noqa: BLE001 - anything else is what this target looks for
        return "%s: %s" % (type(e).__name__, e)
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seconds", type=float, default=None)
    parser.add_argument("--cases", type=int, default=500)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    warnings.simplefilter("ignore")  # numpy's overflow warnings on the hostile casts
    np.seterr(all="ignore")
    plane = freeform.make_plane(12, 12)
    start, n, bad = time.monotonic(), 0, 0
    while (time.monotonic() - start < args.seconds) if args.seconds is not None else n < args.cases:
        seed = args.seed * 1_000_003 + n
        problem = one_case(seed, plane)
        if problem:
            bad += 1
            print("case seed %d: %s" % (seed, problem[:300]), flush=True)
        n += 1
    print("python api fuzz: %d cases, %d unexpected exceptions" % (n, bad))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
