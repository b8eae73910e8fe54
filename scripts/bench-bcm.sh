#!/usr/bin/env bash
# BCM engine benchmarks (docs/benchmarks.md, "BCM engine"): builds the release bench_bcm and
# runs it; prints Google Benchmark JSON (medians; 3 repetitions up to 35k free vertices, 1
# beyond) to stdout and keeps a copy in <build>/bench-bcm.json. A second, separate process
# precomputes only the 300k k = 3 case so that its peak RSS (getrusage, counter peak_rss_mb)
# is not mixed with other cases; that JSON goes to <build>/bench-bcm-peak-300k.json.
# Extra arguments go to the main bench run, e.g. --benchmark_filter=Evaluate.
# BUILD_DIR=path uses an existing configured build folder instead of the release preset.
# Takes about 10 minutes on the 2-core dev box.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh >&2
scripts/fetch-data.sh >&2
if [[ -n "${BUILD_DIR:-}" ]]; then
  build=$BUILD_DIR
  cmake --build "$build" --target bench_bcm -j2 >&2
else
  build=build/release
  cmake --preset release >&2
  cmake --build --preset release --target bench_bcm >&2
fi
"$build/bench/bench_bcm" --benchmark_filter='BM_BcmPrecompute/kfree:300/k:3/blended:0' \
  --benchmark_format=console --benchmark_out="$build/bench-bcm-peak-300k.json" --benchmark_out_format=json >&2
"$build/bench/bench_bcm" --benchmark_report_aggregates_only=true \
  --benchmark_format=console --benchmark_out="$build/bench-bcm.json" --benchmark_out_format=json "$@" >&2
cat "$build/bench-bcm.json"
