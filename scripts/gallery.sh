#!/usr/bin/env bash
# The gallery benchmark (docs/nonlinear.md, "Gallery"): builds bench_gallery, runs every case
# against CGAL's ARAP and SR-ARAP, prints the summary and renders a contact sheet of the cases
# (rest | Freeform k = 3 | CGAL ARAP, close-ups of what moved) with `freeform render`.
#   scripts/gallery.sh [OUT_DIR=build/gallery] [bench_gallery options, e.g. --quick]
# Writes OUT_DIR/gallery.json, OUT_DIR/summary.md and OUT_DIR/contact-sheet-N.png (20 cases a page).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
out=${1:-build/gallery}
shift || true
scripts/bootstrap.sh
scripts/fetch-data.sh
# The sheets' labels need a font ImageMagick finds by name (its default, Helvetica, is not installed).
font=/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf
if ! command -v montage >/dev/null || [ ! -f "$font" ]; then
  apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends imagemagick fonts-dejavu-core
fi
cmake --preset release >/dev/null
cmake --build --preset release --target bench_gallery freeform
mkdir -p "$out/meshes" "$out/png"
build/release/bench/bench_gallery --out "$out/meshes" "$@" > "$out/gallery.json"
scripts/gallery-summary.py "$out/gallery.json" | tee "$out/summary.md"
tiles=()
for rest in "$out"/meshes/*-rest.off; do
  case_name=$(basename "$rest" -rest.off)
  up=y
  case "$case_name" in flat-cylinder* | bar* | cylinder*) up=z ;; esac
  # Close-up of what the edit moved (rest, Freeform and ARAP framed alike).
  camera=$(scripts/gallery-camera.py "$up" "$rest" "$out/meshes/$case_name"-{freeform,arap}.off 2>/dev/null ||
           scripts/gallery-camera.py "$up" "$rest" "$out/meshes/$case_name-freeform.off")
  for kind in rest freeform arap; do
    mesh="$out/meshes/$case_name-$kind.off"
    [ -f "$mesh" ] || continue
    build/release/freeform render "$mesh" --camera "$camera" --size 320x320 -o "$out/png/$case_name-$kind.png" >/dev/null
    tiles+=("$out/png/$case_name-$kind.png")
  done
done
# Pages of 20 cases: one sheet of all 103 exceeds ImageMagick's default size limit.
rm -f "$out"/contact-sheet-*.png
per_page=60
for ((i = 0, page = 1; i < ${#tiles[@]}; i += per_page, page++)); do
  montage -font "$font" -label '%t' "${tiles[@]:i:per_page}" -tile 3x -geometry +2+2 -title "rest | Freeform k=3 | CGAL ARAP" \
    "$out/contact-sheet-$page.png"
done
echo "gallery: wrote $out/gallery.json, $out/summary.md and $out/contact-sheet-*.png"
