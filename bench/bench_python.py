#!/usr/bin/env python3
"""The Python module's per-frame cost against the C++ frame (docs/benchmarks.md, "Python module").

Setup of bench/bench_multires.cpp: make_bumpy_plane(222, 222, 0.01, 12) (49.7k vertices), support
0.1 <= x <= 0.9 (35.1k free vertices), one handle strip 0.45 <= x <= 0.55, k = 2, multiresolution.
Timed in one process, in interleaved blocks so machine load hits all of them alike:
  cpp           EditSolver::evaluate in a C++ loop (solver._time_evaluate: no Python in the loop)
  cpp_copy      the same plus evaluate_into's copy of the touched rows (copy=True)
  evaluate_into solver.evaluate_into(out, [m]) from Python (no allocation, writes touched rows)
  evaluate      solver.evaluate([m]) from Python (a new 49.7k x 3 array per frame)
and, on a 12 x 12 plane whose frame costs a few microseconds, the same pair for the pure call
overhead. Target: evaluate_into <= 1.2 x cpp + 10 us (medians). Prints JSON.

Run: PYTHONPATH=build/release/python /usr/bin/python3 bench/bench_python.py [--rounds 40]
"""
import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

import freeform


def strip_edit(mesh, lo=0.1, hi=0.9, handle=(0.45, 0.55)):
    x = mesh.vertices[:, 0]
    support = np.flatnonzero((x >= lo) & (x <= hi))
    strip = np.flatnonzero((x >= handle[0]) & (x <= handle[1]))
    return freeform.Edit.from_dict({"order": 2, "support": {"vertices": support},
                                    "handles": [{"region": {"vertices": strip}}]}, mesh)


def moved():
    a = 0.2  # as bench_multires: up 0.1, rotated 0.2 rad about y
    m = np.eye(4)
    m[:3, :3] = [[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]]
    m[2, 3] = 0.1
    return m


def measure(solver, rounds, block):
    out = solver.mesh.vertices
    transforms = [moved()]
    samples = {"cpp": [], "cpp_copy": [], "evaluate_into": [], "evaluate": []}
    clock = time.perf_counter_ns
    for _ in range(3):  # warm up
        solver.evaluate_into(out, transforms)
    for _ in range(rounds):
        samples["cpp"].extend(solver._time_evaluate(block, transforms).tolist())
        samples["cpp_copy"].extend(solver._time_evaluate(block, transforms, copy=True).tolist())
        for _ in range(block):
            t0 = clock()
            solver.evaluate_into(out, transforms)
            samples["evaluate_into"].append((clock() - t0) * 1e-9)
        for _ in range(block):
            t0 = clock()
            solver.evaluate(transforms)
            samples["evaluate"].append((clock() - t0) * 1e-9)
    assert np.array_equal(out, solver.evaluate(transforms))
    return {k: statistics.median(v) for k, v in samples.items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=40, help="interleaved blocks (default 40)")
    parser.add_argument("--block", type=int, default=25, help="frames per block (default 25)")
    parser.add_argument("--n", type=int, default=222, help="grid size (222: 35.1k free vertices)")
    args = parser.parse_args()

    mesh = freeform.make_bumpy_plane(args.n, args.n, 0.01, 12)
    t0 = time.perf_counter()
    solver = freeform.EditSolver(mesh, strip_edit(mesh))
    precompute_s = time.perf_counter() - t0
    big = measure(solver, args.rounds, args.block)

    tiny_mesh = freeform.make_plane(12, 12)
    tiny = measure(freeform.EditSolver(tiny_mesh, strip_edit(tiny_mesh, 0.2, 0.8, (0.4, 0.6))),
                   args.rounds, 10 * args.block)

    ms, us = 1e3, 1e6
    overhead = big["evaluate_into"] - big["cpp"]
    result = {
        "mesh": f"make_bumpy_plane({args.n}, {args.n}, 0.01, 12)",
        "vertices": mesh.n_vertices,
        "free": solver.stats["counts"]["free"],
        "touched": len(solver.touched),
        "precompute_s": round(precompute_s, 3),
        "frames_per_kind": args.rounds * args.block,
        "median_ms": {k: round(v * ms, 4) for k, v in big.items()},
        "evaluate_into_over_cpp": round(big["evaluate_into"] / big["cpp"], 3),
        "evaluate_into_minus_cpp_us": round(overhead * us, 1),
        "tiny_plane_median_us": {"vertices": tiny_mesh.n_vertices, **{k: round(v * us, 2) for k, v in tiny.items()},
                                 "call_overhead": round((tiny["evaluate_into"] - tiny["cpp_copy"]) * us, 2)},
        "target": "evaluate_into <= 1.2 x cpp + 10 us",
        "target_met": big["evaluate_into"] <= 1.2 * big["cpp"] + 10e-6,
        "load_average": [round(x, 2) for x in os.getloadavg()],
        "omp": {k: os.environ[k] for k in ("OMP_NUM_THREADS", "OMP_WAIT_POLICY") if k in os.environ},
        "python": sys.version.split()[0],
        "numpy": np.__version__,
    }
    print(json.dumps(result, indent=2))


if __name__ == "__main__":
    main()
