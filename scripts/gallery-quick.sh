#!/usr/bin/env bash
# The gallery's quick loop (docs/nonlinear.md, "Gallery"): Freeform alone on the gallery's cases,
# or with --assimp on the assimp-testmodels files, compared with CGAL's ARAP runs of the same cases
# stored in data/gallery/ (each case checked to be the same edit: gallery-summary.py --peer-from);
# with --scales, --turns or --bumps (bench_gallery's edit families) against those families' stored runs.
# A minute for --config k2 --config k3, against 40 min for a run with the peer (scripts/gallery.sh).
#   scripts/gallery-quick.sh [OUT_DIR=build/gallery-quick] [bench_gallery options, e.g. --config k2 --assimp]
# Writes OUT_DIR/gallery.json and prints the summary. When the cases change, store the peer again:
#   bench_gallery --config k2 [--assimp | --scales | --turns | --bumps] > peer.json
#   scripts/gallery-summary.py peer.json --save-peer data/gallery/cgal-arap[-assimp|-scales|-turns|-bumps].json
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
out=build/gallery-quick
# An option first means OUT_DIR was left out, not that it is named like an option.
if [[ $# -gt 0 && $1 != --* ]]; then
  out=$1
  shift
fi
peer=data/gallery/cgal-arap.json
for option in "$@"; do
  case "$option" in
    --assimp) peer=data/gallery/cgal-arap-assimp.json ;;
    --scales) peer=data/gallery/cgal-arap-scales.json ;;
    --bumps) peer=data/gallery/cgal-arap-bumps.json ;;
    --turns) peer=data/gallery/cgal-arap-turns.json ;;
    --drags) echo "gallery-quick: --drags: no stored peer; run scripts/gallery.sh OUT --drags" >&2; exit 2 ;;
    --mesh) echo "gallery-quick: --mesh: no stored peer for other files; run bench_gallery with the peer" >&2; exit 2 ;;
  esac
done
scripts/bootstrap.sh >/dev/null
scripts/fetch-data.sh >/dev/null
cmake --preset release >/dev/null
cmake --build --preset release --target bench_gallery >/dev/null
mkdir -p "$out"
# The per-case table goes to cases.txt; on failure its end (the error) is shown.
if ! FREEFORM_MESH_DIR="${FREEFORM_MESH_DIR:-$root/.cache/cgal-meshes}" build/release/bench/bench_gallery --no-peer "$@" \
  > "$out/gallery.json.tmp" 2>"$out/cases.txt"; then
  tail -n 5 "$out/cases.txt" >&2
  rm -f "$out/gallery.json.tmp"
  exit 1
fi
mv "$out/gallery.json.tmp" "$out/gallery.json"
scripts/gallery-summary.py "$out/gallery.json" --peer-from "$peer"
