#!/usr/bin/env bash
# Builds and runs the whole test suite: release build (warnings are errors), the Python suite
# against the wheel installed in a fresh virtualenv, then the release suite under
# AddressSanitizer + UndefinedBehaviorSanitizer. Installs what is missing first.
# FREEFORM_SKIP_ASAN=1 runs only the release suite.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
# ccache (installed by bootstrap.sh): paths relative to the clone, so another clone reuses the objects.
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
scripts/bootstrap.sh
scripts/check-code-shape.py
scripts/fetch-data.sh
export FREEFORM_REQUIRE_DATA=1
cmake --preset release
cmake --build --preset release
ctest --preset release
scripts/test-wheel.sh
if [ "${FREEFORM_SKIP_ASAN:-0}" != 1 ]; then
  cmake --preset asan
  cmake --build --preset asan
  ctest --preset asan
fi
