#!/usr/bin/env bash
# The main job on the bundled default input: installs what is missing, builds the release
# CLI and runs it on the armadillo of libcgal-demo.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh
scripts/fetch-data.sh
cmake --preset release >/dev/null
cmake --build --preset release --target freeform
mesh=.cache/cgal-meshes/armadillo.off
out=build/demo
mkdir -p "$out"
./build/release/freeform info "$mesh"
./build/release/freeform info "$mesh" --json > "$out/armadillo-info.json"
./build/release/freeform convert "$mesh" "$out/armadillo.ply"
echo "demo: wrote $out/armadillo-info.json and $out/armadillo.ply"
