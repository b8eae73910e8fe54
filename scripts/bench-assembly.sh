#!/usr/bin/env bash
# The BCM system's assembly on one thread and on all (issue 43; docs/benchmarks.md, "Precompute
# on all cores"): bench_assembly with FREEFORM_THREADS=1, then with every core; a JSON array.
# Usage: scripts/bench-assembly.sh [mesh subdivisions free_in_thousands k repeats]
# Default: bunny00.off subdivided 3 times, 1000k free, k = 3, 3 repeats (about 2 min, 6 GB).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh >&2
scripts/fetch-data.sh >&2
cmake --preset release >&2
cmake --build --preset release --target bench_assembly >&2
if [ $# -eq 0 ]; then set -- bunny00.off 3 1000 3 3; fi
one=$(FREEFORM_THREADS=1 FREEFORM_MESH_DIR="$root/.cache/cgal-meshes" build/release/bench/bench_assembly "$@")
all=$(FREEFORM_MESH_DIR="$root/.cache/cgal-meshes" build/release/bench/bench_assembly "$@")
printf '[%s,\n%s]\n' "$one" "$all"
