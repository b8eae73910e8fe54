#!/usr/bin/env bash
# Ordering benchmark (issue 43; docs/benchmarks.md, "Precompute on all cores"): METIS on the whole
# BCM graph against the nested dissection that orders its parts concurrently, with each task's
# own time (what `parts` cores would take). JSON on stdout.
# Usage: scripts/bench-ordering.sh [mesh subdivisions free_in_thousands k parts...]
# Default: bunny00.off subdivided 3 times, 1000k free, k = 3, 2 / 4 / 16 parts (about 2 min).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh >&2
scripts/fetch-data.sh >&2
cmake --preset release >&2
cmake --build --preset release --target bench_ordering >&2
if [ $# -eq 0 ]; then set -- bunny00.off 3 1000 3 2 4 16; fi
FREEFORM_MESH_DIR="$root/.cache/cgal-meshes" build/release/bench/bench_ordering "$@"
