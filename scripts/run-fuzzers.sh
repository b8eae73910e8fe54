#!/usr/bin/env bash
# Builds the libFuzzer targets (CMake preset `fuzz`, clang) and runs each one: the mesh readers
# (obj off ply stl gltf), edit files (edit), .sel/.def files (seldef) and editor sessions (session);
# then the Python module's entry points (python: fuzz/fuzz_python_api.py on the release build).
#
#   scripts/run-fuzzers.sh [seconds-per-target] [target ...]     (default 60, all targets)
#
# Seeds come from data/tiny (gltf: the assimp-testmodels glTF2 samples under 64 KiB, when
# installed), copied into a scratch corpus under build/fuzz/corpus, not in git (FUZZ_WORK_DIR
# overrides the location). Crash reproducers are written to <work>/artifacts/<fmt>/.
# Exits non-zero if any fuzzer found a crash, leak, timeout or out-of-memory input.
set -euo pipefail

seconds="${1:-60}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
work="${FUZZ_WORK_DIR:-$root/build/fuzz/corpus}"
shift || true
targets=(obj off ply stl gltf edit seldef session python)
[ "$#" -gt 0 ] && targets=("$@")
native=()
for t in "${targets[@]}"; do [ "$t" != python ] && native+=("$t"); done

if [ "${#native[@]}" -gt 0 ]; then
  cmake --preset fuzz >/dev/null
  cmake --build --preset fuzz --target "${native[@]/#/fuzz_}" -j "${FUZZ_JOBS:-2}"
fi

status=0
summary=""
for t in "${targets[@]}"; do
  if [ "$t" = python ]; then
    # Random dicts and arrays through Edit.from_dict, Mesh(V, F) and EditSolver; a crash is a
    # signal here, an undocumented exception exit 1.
    cmake --preset release >/dev/null && cmake --build --preset release --target freeform_python >/dev/null
    echo "== python api: ${seconds}s"
    rc=0
    PYTHONPATH=build/release/python /usr/bin/python3 -X dev fuzz/fuzz_python_api.py --seconds "$seconds" \
        >"$work/fuzz_python.log" 2>&1 || rc=$?
    if [ "$rc" -ne 0 ]; then
      status=1
      summary+="python api: FAILED (exit $rc), see $work/fuzz_python.log"$'\n'
      tail -n 20 "$work/fuzz_python.log"
    else
      summary+="python api: ok, $(tail -n 1 "$work/fuzz_python.log")"$'\n'
    fi
    continue
  fi
  corpus="$work/$t"
  artifacts="$work/artifacts/$t/"
  mkdir -p "$corpus" "$artifacts"
  case "$t" in
    edit) seeds=(data/edits/*.json) ;;
    session) seeds=(fuzz/seeds/session.json) ;;
    seldef)  # first byte: 0 = .sel, 1 = .def
      for f in data/edits/*.sel data/edits/*.def; do
        { [ "${f##*.}" = sel ] && printf 0 || printf 1; cat "$f"; } >"$corpus/seed-$(basename "$f")"
      done
      seeds=() ;;
    gltf)  # /usr/share/assimp/models/glTF2 (assimp-testmodels): the small .gltf and .glb samples
      if [ -d /usr/share/assimp/models/glTF2 ]; then
        while IFS= read -r -d '' f; do
          rel="${f#/usr/share/assimp/models/glTF2/}"
          cp "$f" "$corpus/seed-${rel//\//_}"
        done < <(find /usr/share/assimp/models/glTF2 -type f \( -name '*.gltf' -o -name '*.glb' \) -size -64k -print0)
      fi
      seeds=() ;;
    *) seeds=(data/tiny/*."$t") ;;
  esac
  for seed in "${seeds[@]}"; do
    [ -e "$seed" ] && cp "$seed" "$corpus/"
  done
  dict=()
  [ -f "fuzz/$t.dict" ] && dict=(-dict="fuzz/$t.dict")
  log="$work/fuzz_$t.log"
  echo "== fuzz_$t: ${seconds}s, corpus $corpus"
  rc=0
  "build/fuzz/fuzz/fuzz_$t" "$corpus" "${dict[@]}" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=1024 \
      -artifact_prefix="$artifacts" -print_final_stats=1 >"$log" 2>&1 || rc=$?
  execs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')"
  crashes="$(find "$artifacts" -type f | wc -l)"
  if [ "$rc" -ne 0 ] || [ "$crashes" -ne 0 ]; then
    status=1
    summary+="fuzz_$t: FAILED (exit $rc, $crashes artifact(s) in $artifacts), execs $execs"$'\n'
    tail -n 40 "$log"
  else
    summary+="fuzz_$t: ok, ${seconds}s, execs $execs, corpus $(find "$corpus" -type f | wc -l) files"$'\n'
  fi
done
echo "== summary"
printf '%s' "$summary"
exit "$status"
