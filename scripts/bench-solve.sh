#!/usr/bin/env bash
# Solve benchmark (issue 43; docs/benchmarks.md, "Precompute on all cores"): the factor's solve
# subtree by subtree on all cores against CHOLMOD's own, alternating, on the same factor of the
# BCM system. JSON on stdout. FREEFORM_THREADS=1 for one core.
# Usage: scripts/bench-solve.sh [mesh subdivisions free_in_thousands k repeats]
# Default: bunny00.off subdivided 2 times, 300k free, k = 3, 5 repeats (about 1 min).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh >&2
scripts/fetch-data.sh >&2
cmake --preset release >&2
cmake --build --preset release --target bench_solve >&2
if [ $# -eq 0 ]; then set -- bunny00.off 2 300 3 5; fi
FREEFORM_MESH_DIR="$root/.cache/cgal-meshes" build/release/bench/bench_solve "$@"
