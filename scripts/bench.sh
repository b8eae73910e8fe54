#!/usr/bin/env bash
# Builds the release benchmarks and runs them; prints Google Benchmark JSON (medians over
# repetitions) to stdout and keeps a copy in build/bench-foundation.json.
# Extra arguments go to the bench binary, e.g. --benchmark_filter=Load.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh >&2
scripts/fetch-data.sh >&2
cmake --preset release >&2
cmake --build --preset release --target bench_foundation >&2
./build/release/bench/bench_foundation --benchmark_repetitions="${REPS:-5}" --benchmark_report_aggregates_only=true \
  --benchmark_format=console --benchmark_out=build/bench-foundation.json --benchmark_out_format=json "$@" >&2
cat build/bench-foundation.json
