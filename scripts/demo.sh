#!/usr/bin/env bash
# The main job on the bundled default input: installs what is missing, builds the release
# CLI and runs a real BCM edit on the armadillo of libcgal-demo: the right ear (geodesic
# support of radius 32 around its tip) is bent outward by a handle at the tip
# (data/edits/armadillo.json, order 3). Writes the deformed mesh and a JSON report.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
# ccache (installed by bootstrap.sh): paths relative to the clone, so another clone reuses the objects.
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
scripts/bootstrap.sh
scripts/fetch-data.sh
cmake --preset release >/dev/null
cmake --build --preset release --target freeform
mesh=.cache/cgal-meshes/armadillo.off
edit=data/edits/armadillo.json
out=build/demo
mkdir -p "$out"
./build/release/freeform info "$mesh"
./build/release/freeform deform "$mesh" --edit "$edit" -o "$out/armadillo-deformed.off" \
  --report "$out/armadillo-report.json"
cat "$out/armadillo-report.json"
./build/release/freeform render "$mesh" --edit "$edit" --up y --view back -o "$out/armadillo-edit.png"
echo "demo: wrote $out/armadillo-deformed.off, $out/armadillo-report.json and $out/armadillo-edit.png"
