#!/usr/bin/env bash
# Screenshots of the Blender add-on in a real Blender window (Xvfb + Mesa llvmpipe, xdotool) for
# docs/blender.md: writes docs/images/blender-{panel,modal,progress}.png.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/blender-addon.sh >/dev/null
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
FREEFORM_BLENDER_ZIP=$root/build/blender/freeform_blender.zip FREEFORM_SHOTS=$root/docs/images \
BLENDER_USER_SCRIPTS=$tmp/scripts BLENDER_USER_CONFIG=$tmp/config LIBGL_ALWAYS_SOFTWARE=1 \
  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup \
  --python scripts/blender_screenshots.py
