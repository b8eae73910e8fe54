#!/usr/bin/env bash
# Builds the self-contained wheel of the Python package into dist/ (docs/python.md), installing
# what the build needs first (scripts/bootstrap.sh). Then: pip install dist/freeform-*.whl
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
scripts/bootstrap.sh
/usr/bin/python3 -m build --wheel --no-isolation --outdir dist
ls -l dist/freeform-*.whl
