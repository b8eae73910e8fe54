#!/usr/bin/env bash
# Scale benchmark (issue 13; docs/benchmarks.md, "Scale"): `freeform deform` on a large support,
# its report's timings, forward error and peak memory as one JSON object on stdout.
# Usage: scripts/bench-scale.sh [mesh subdivisions free_in_thousands k]
# Default: bunny00.off subdivided 3 times (2.4M vertices), 1000k free, k = 3 (several minutes,
# ~5 GB). E.g. scripts/bench-scale.sh bunny00.off 2 140 3 for a quick one.
# FREEFORM_WRAP: a command put before freeform (e.g. "perf record -o /tmp/p.data").
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
mesh=${1:-bunny00.off} subdivisions=${2:-3} free=${3:-1000} k=${4:-3}
scripts/bootstrap.sh >&2
scripts/fetch-data.sh >&2
build=build/release
cmake --preset release >&2
cmake --build --preset release --target bench_scale freeform >&2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
read -r mesh_file edit_file vertices < <(FREEFORM_MESH_DIR="$root/.cache/cgal-meshes" "$build/bench/bench_scale" "$work" "$mesh" "$subdivisions" "$free" "$k")
start=$(date +%s.%N)
${FREEFORM_WRAP:-} "$build/freeform" deform "$mesh_file" --edit "$edit_file" -o "$work/out.ply" --report "$work/report.json" >&2
end=$(date +%s.%N)
python3 - "$work/report.json" "$mesh" "$subdivisions" "$vertices" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
t = r["timings_ms"]
print(json.dumps({
    "mesh": f"{sys.argv[2]} subdivided {sys.argv[3]}x", "vertices": int(sys.argv[4]), "free": r["counts"]["free"],
    "order": r["order"], "solver": r["solver"], "deform_wall_s": round(float(sys.argv[6]) - float(sys.argv[5]), 1),
    # decomposition_ms includes operator_shape_ms (MultiresStats)
    "precompute_ms": t["assembly"] + t["factorization"] + t["basis"] + t["refinement"]
                     + r["multiresolution"]["decomposition_ms"],
    "timings_ms": t, "multiresolution_ms": {k: r["multiresolution"][k] for k in ("decomposition_ms", "operator_shape_ms", "reconstruct_ms")},
    "precompute": r["precompute"], "forward_error": r["forward_error"], "refinement": r["refinement"], "residual": r["residual"],
    "peak_memory_mb": r["peak_memory_mb"]}, indent=1))
PY
