#!/usr/bin/env bash
# The Python package as users install it (docs/python.md): builds the wheel, installs it into a
# fresh virtualenv and runs tests/python against the installed package from outside the source
# tree (FREEFORM_INSTALLED=1 adds the checks of the installed wheel: only bundled libraries,
# and the demo where Debian's SuiteSparse, METIS and OpenBLAS are hidden). Needs the release
# build's CLI (the tests compare with it): scripts/test.sh runs this after the release suite.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
export CCACHE_BASEDIR="$root" CCACHE_NOHASHDIR=1
scripts/bootstrap.sh
dist=build/dist
rm -rf "$dist"
/usr/bin/python3 -m build --wheel --no-isolation --outdir "$dist" >build/wheel.log 2>&1 || { tail -40 build/wheel.log; exit 1; }
wheel=$(ls "$dist"/freeform-*.whl)
echo "test-wheel: $wheel, $(du -h "$wheel" | cut -f1)"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
venv="$work/venv"
/usr/bin/python3 -m venv --system-site-packages "$venv"
"$venv/bin/pip" install --no-index --quiet "$wheel"
cd "$work"
FREEFORM_INSTALLED=1 FREEFORM_CLI="$root/build/release/freeform" FREEFORM_MESH_DIR="$root/.cache/cgal-meshes" \
  FREEFORM_DATA_DIR="$root/data" PYTHONDONTWRITEBYTECODE=1 \
  "$venv/bin/python" -X dev -m pytest -q -p no:cacheprovider -rs "$root/tests/python"
