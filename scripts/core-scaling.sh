#!/usr/bin/env bash
# Issue 43's measurement on a machine with more cores and none of Debian's packages
# (docs/benchmarks.md, "Precompute on all cores"): the same binary with all cores and pinned to 2.
#   scripts/core-scaling.sh pack          here: builds the release `freeform` and `bench_scale` and
#                                         writes build/core-scaling.tar.xz (the binaries, every library
#                                         they load with glibc's own loader, the meshes they need)
#   scripts/core-scaling.sh run [CASES]   there, in a checkout holding that file: unpacks it, makes each
#                                         case with bench_scale and runs `freeform deform` on all cores,
#                                         then pinned to cores 0 and 1 (taskset, FREEFORM_THREADS=2)
# CASES: mesh:subdivisions:free_in_thousands:k, default "bunny00.off:2:300:3 bunny00.off:3:1000:3".
# `run` needs only a shell, coreutils, tar and xz; without taskset the 2-core run is capped by
# FREEFORM_THREADS alone ("pinned": false). One JSON object per run on stdout: the case, the
# threads, the wall time and freeform's whole report (per-phase wall and CPU time in "precompute").
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
pack=build/core-scaling.tar.xz
work=""
trap '[ -z "$work" ] || rm -rf "$work"' EXIT

pack() {
  scripts/bootstrap.sh >&2
  scripts/fetch-data.sh >&2
  cmake --preset release >&2
  cmake --build --preset release --target freeform bench_scale >&2
  work=$(mktemp -d)
  local stage=$work
  mkdir -p "$stage/bin" "$stage/lib" "$stage/meshes"
  cp build/release/freeform build/release/bench/bench_scale "$stage/bin/"
  # Every library either binary loads, the loader included, resolved through symlinks and
  # alternatives to the files themselves.
  ldd build/release/freeform build/release/bench/bench_scale | awk '/=> \// {print $1, $3} /^\t\/.*ld-linux/ {print "ld-linux-x86-64.so.2", $1}' |
    sort -u | while read -r name path; do cp -L "$path" "$stage/lib/$name"; done
  cp .cache/cgal-meshes/bunny00.off "$stage/meshes/"
  tar -C "$stage" -cJf "$pack.tmp" bin lib meshes
  mv "$pack.tmp" "$pack"
  echo "core-scaling: wrote $pack ($(du -h "$pack" | cut -f1)); carry it and run: scripts/core-scaling.sh run" >&2
}

# Runs a packed binary through the packed loader, whatever glibc the machine has.
packed() {
  local dir=$1 exe=$2
  shift 2
  "$dir/lib/ld-linux-x86-64.so.2" --library-path "$dir/lib" "$dir/bin/$exe" "$@"
}

one_run() {  # dir case_name mesh_file edit_file setting [taskset...]
  local dir=$1 name=$2 mesh_file=$3 edit_file=$4 setting=$5 pinned=$6 threads=$7
  shift 7
  local start end
  start=$(date +%s.%N)
  # The tunable freeform would restart itself with (common/huge_pages.h): through the loader a
  # restart would exec the loader, not freeform.
  GLIBC_TUNABLES=glibc.malloc.hugetlb=1 FREEFORM_THREADS=$threads "$@" "$dir/lib/ld-linux-x86-64.so.2" --library-path "$dir/lib" "$dir/bin/freeform" \
    deform "$mesh_file" --edit "$edit_file" -o "$dir/out.ply" --report "$dir/report.json" >&2
  end=$(date +%s.%N)
  printf '{"case": "%s", "setting": "%s", "threads": %s, "pinned": %s, "cores": %s, "wall_s": %s, "report": %s}\n' \
    "$name" "$setting" "$threads" "$pinned" "$(nproc)" "$(echo "$end - $start" | awk '{print $1 - $3}')" \
    "$(tr -d '\n' < "$dir/report.json")"
}

run() {
  [ -f "$pack" ] || { echo "core-scaling: $pack not found (scripts/core-scaling.sh pack makes it)" >&2; exit 1; }
  work=$(mktemp -d)
  local dir=$work
  tar -C "$dir" -xJf "$pack"
  [ $# -gt 0 ] || set -- bunny00.off:2:300:3 bunny00.off:3:1000:3
  local pin=(taskset -c 0,1) pinned=true
  command -v taskset > /dev/null || { pin=(); pinned=false; }
  for c in "$@"; do
    IFS=: read -r mesh subdivisions free k <<< "$c"
    local mesh_file edit_file vertices
    read -r mesh_file edit_file vertices < <(FREEFORM_MESH_DIR="$dir/meshes" packed "$dir" bench_scale "$dir" "$mesh" "$subdivisions" "$free" "$k")
    local name="$mesh subdivided ${subdivisions}x, ${free}k free, k = $k ($vertices vertices)"
    one_run "$dir" "$name" "$mesh_file" "$edit_file" "all cores" false "$(nproc)"
    one_run "$dir" "$name" "$mesh_file" "$edit_file" "2 cores" "$pinned" 2 "${pin[@]}"
  done
}

case "${1:-}" in
  pack) pack ;;
  run) shift; run "$@" ;;
  *) echo "usage: scripts/core-scaling.sh pack | run [mesh:subdivisions:free_in_thousands:k ...]" >&2; exit 2 ;;
esac
