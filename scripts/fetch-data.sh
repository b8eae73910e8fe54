#!/usr/bin/env bash
# Unpacks the meshes of Debian's libcgal-demo (data.tar.gz, folder data/meshes) into
# .cache/cgal-meshes, where tests and benchmarks look for them (override: FREEFORM_MESH_DIR).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dest=${FREEFORM_MESH_DIR:-$root/.cache/cgal-meshes}
archive=/usr/share/doc/libcgal-demo/data.tar.gz
if [ -f "$dest/.complete" ]; then
  echo "fetch-data: meshes already in $dest"
  exit 0
fi
if [ ! -f "$archive" ]; then
  echo "fetch-data: $archive not found; install libcgal-demo (scripts/bootstrap.sh does)" >&2
  exit 1
fi
mkdir -p "$(dirname "$dest")"
tmp=$(mktemp -d "$(dirname "$dest")/.fetch.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
tar -xzf "$archive" -C "$tmp" --wildcards 'data/meshes/*'
rm -rf "$dest"
mv "$tmp/data/meshes" "$dest"
touch "$dest/.complete"
echo "fetch-data: $(find "$dest" -type f ! -name .complete | wc -l) files in $dest"
