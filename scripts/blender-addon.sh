#!/usr/bin/env bash
# Builds the Blender add-on: the freeform Python module (release) inside the add-on package,
# zipped as build/blender/freeform_blender.zip. Install it in Blender with Preferences >
# Add-ons > Install, or headless:
#   blender -b --python-expr 'import bpy; bpy.ops.preferences.addon_install(filepath="build/blender/freeform_blender.zip"); bpy.ops.preferences.addon_enable(module="freeform_blender"); bpy.ops.wm.save_userpref()'
# The module is built for /usr/bin/python3, the Python Debian's Blender runs (3.11). docs/blender.md
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/bootstrap.sh
cmake --preset release >/dev/null
cmake --build --preset release --target freeform_blender_zip
mkdir -p build/blender
cp build/release/blender/freeform_blender.zip build/blender/freeform_blender.zip.tmp
mv build/blender/freeform_blender.zip.tmp build/blender/freeform_blender.zip
echo "blender-addon: wrote build/blender/freeform_blender.zip"
