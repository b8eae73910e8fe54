#!/usr/bin/env bash
# Regenerates the screenshots of docs/editor.md ("In pictures") from a real, scripted session
# of freeform-editor: Xvfb + xdotool drive the editor on the armadillo of libcgal-demo exactly
# as a user would (clicks on the panel, keys, a gizmo drag), and ImageMagick's `import` grabs
# the screen. Writes docs/images/editor-{support,handle,drag,export,segment}.png (atomically).
#
#   scripts/editor-screenshots.sh                 # editor: build/release/apps/editor/freeform-editor
#   FREEFORM_EDITOR=path/to/freeform-editor scripts/editor-screenshots.sh
#   SHOTS_SLOW=2 scripts/editor-screenshots.sh    # double every pause (busy machine)
#
# The pixel positions below belong to the 1280x800 window, the panel layout of apps/editor and
# the armadillo's "back" view with y up; if one of those changes, take a screenshot, read the
# new positions off it and update them here. Needs Xvfb, xdotool and ImageMagick.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

editor=${FREEFORM_EDITOR:-build/release/apps/editor/freeform-editor}
slow=${SHOTS_SLOW:-1}
mesh=.cache/cgal-meshes/armadillo.off
out=docs/images

if [ ! -x "$editor" ]; then
  echo "editor-screenshots: $editor not found; build it first:" >&2
  echo "  cmake --preset release && cmake --build --preset release --target freeform-editor" >&2
  echo "  (or point FREEFORM_EDITOR at a freeform-editor binary)" >&2
  exit 1
fi
for tool in Xvfb xdotool; do
  command -v "$tool" >/dev/null || { echo "editor-screenshots: $tool missing (apt-get install xvfb xdotool)" >&2; exit 1; }
done
if ! command -v import >/dev/null; then
  apt-get install -y imagemagick >/dev/null || { echo "editor-screenshots: install ImageMagick (import)" >&2; exit 1; }
fi
[ -f "$mesh" ] || scripts/fetch-data.sh

# A private X display and config folder (no recent files of the user, nothing written to ~).
display=
for n in $(seq 61 199); do
  if [ ! -e "/tmp/.X$n-lock" ] && [ ! -e "/tmp/.X11-unix/X$n" ]; then display=":$n"; break; fi
done
[ -n "$display" ] || { echo "editor-screenshots: no free X display in :61..:199" >&2; exit 1; }
tmp=$(mktemp -d)
xvfb_pid= editor_pid=
cleanup() {
  [ -n "$editor_pid" ] && kill "$editor_pid" 2>/dev/null && wait "$editor_pid" 2>/dev/null
  [ -n "$xvfb_pid" ] && kill "$xvfb_pid" 2>/dev/null && wait "$xvfb_pid" 2>/dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

pause() { sleep "$(awk -v s="$1" -v k="$slow" 'BEGIN { print s * k }')"; }
x() { DISPLAY=$display xdotool "$@"; }
alive() {
  kill -0 "$editor_pid" 2>/dev/null && return 0
  echo "editor-screenshots: the editor exited; its log:" >&2
  cat "$tmp/editor.log" >&2
  exit 1
}
# Click at (x, y): ImGui reads the pointer once per frame, so wait between move and press.
click_at() { x mousemove "$1" "$2" sleep 0.4 click 1; pause 1.2; alive; }
# Left drag from (x0, y0) to (x1, y1) in `steps` moves; `hold` leaves the button down.
drag() {
  local x0=$1 y0=$2 x1=$3 y1=$4 steps=$5 button=${6:-1} args i
  args=(mousemove "$x0" "$y0" sleep 0.4 mousedown "$button")
  for i in $(seq 1 "$steps"); do
    args+=(sleep 0.2 mousemove $((x0 + (x1 - x0) * i / steps)) $((y0 + (y1 - y0) * i / steps)))
  done
  x "${args[@]}" sleep 0.5
}
# The flood radius slider: Ctrl+click turns it into a text field; type the value, Enter.
flood_radius() {
  x mousemove 80 346 sleep 0.4 keydown ctrl sleep 0.4 click 1 sleep 0.4 keyup ctrl
  pause 0.8
  x key ctrl+a sleep 0.2 type --delay 80 "$1"
  pause 0.4
  x key Return
  pause 1
}
# Screenshot with the pointer parked on the status bar (no brush circle, no tooltip).
shot() {
  local name=$1 park=${2:-yes}
  [ "$park" = yes ] && x mousemove 1279 799 && pause 1
  alive
  DISPLAY=$display import -window root "png:$tmp/$name.png"
  cp "$tmp/$name.png" "$out/.$name.png.tmp"
  mv "$out/.$name.png.tmp" "$out/$name.png"
  echo "editor-screenshots: $out/$name.png ($(($(stat -c %s "$out/$name.png") / 1024)) KB)"
}

start=$(date +%s)
Xvfb "$display" -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 &
xvfb_pid=$!
for _ in $(seq 100); do DISPLAY=$display xdpyinfo >/dev/null 2>&1 && break; sleep 0.1; done
DISPLAY=$display HOME=$tmp XDG_CONFIG_HOME=$tmp/config "$editor" "$mesh" --size 1280x800 >"$tmp/editor.log" 2>&1 &
editor_pid=$!
for _ in $(seq 300); do
  alive
  x search --onlyvisible --name freeform >/dev/null 2>&1 && break
  sleep 0.2
done
pause 3

# View: up axis y (the armadillo is y-up), preset "back" (its face), then orbit a little
# (middle drag 40 px right, 10 down) for a three-quarter view, and F to fit.
click_at 113 186                      # View > Up axis > y
click_at 112 162                      # the preset combo ...
click_at 91 203                       # ... "back"
drag 1200 400 1240 410 4 2; x mouseup 2; pause 1
x mousemove 800 500 sleep 0.3 key f; pause 1

if [ "${1:-}" = nonlinear ]; then
  # The arm (flood 70 from the fist), the handle at the fist, multiresolution off, nonlinear
  # on; R rotates the handle about the view axis while the pointer circles the pivot (1085,
  # 212); the shot is taken mid-drag, with the panel's "(predicted, refining)" status.
  flood_radius 70
  x mousemove 800 500 sleep 0.3 key 1 sleep 0.3 key o; pause 0.5
  click_at 1070 215
  flood_radius 15
  x mousemove 800 500 sleep 0.3 key 2; pause 0.5
  click_at 1090 212
  pause 4
  click_at 125 556                    # multiresolution off
  pause 4
  click_at 17 579                     # nonlinear on
  pause 8
  x mousemove 1085 400 sleep 0.5 key r sleep 0.5
  for a in $(seq 6 6 96); do
    x mousemove "$(awk -v a="$a" 'BEGIN { printf "%d", 1085 - 188 * sin(a * 3.14159 / 180) }')" \
      "$(awk -v a="$a" 'BEGIN { printf "%d", 212 + 188 * cos(a * 3.14159 / 180) }')" sleep 0.05
  done
  shot editor-nonlinear no
  x click 1; pause 1
  echo "editor-screenshots: done in $(($(date +%s) - start)) s"
  exit 0
fi

# 1. Support: flood tool (O) in support mode (1), flood radius 45, one click on the left fist
#    (the armadillo's left; on screen right): every vertex within 45 along the surface, all
#    around the forearm (the brush and lasso paint only the visible side).
flood_radius 45
x mousemove 800 500 sleep 0.3 key 1 sleep 0.3 key o; pause 0.5
click_at 1070 215
pause 1
shot editor-support

# 2. Handle: paint mode handle (2), flood radius 15, a click at the tip of the fist. The gizmo
#    appears; the solver is precomputed in the background ("solver ready").
flood_radius 15
x mousemove 800 500 sleep 0.3 key 2; pause 0.5
click_at 1090 212
pause 5
shot editor-handle

# 3. Drag the gizmo's green (Y) arrow up by 90 px; the screenshot is taken before the release,
#    with the running "Grab Y (global)" amount next to the cursor and on the status line.
drag 1085 188 1085 98 10
pause 1.5
shot editor-drag no
x mouseup 1; pause 1.5

# 4. Ctrl+E: the export prompt, with the suggested path selected (Esc closes it unused).
x mousemove 800 500 sleep 0.3 key ctrl+e; pause 1.5
shot editor-export
x key Escape; pause 0.5

# 5. Boundary smoothness: paint mode boundary (4), flood radius 12, a click on the band at the
#    support's outer boundary on the upper arm makes a C0 segment (red; the rest of the band is
#    violet, C2), shown after the background precompute.
flood_radius 12
x mousemove 800 500 sleep 0.3 key 4; pause 0.5
click_at 940 255
pause 5
shot editor-segment

echo "editor-screenshots: done in $(($(date +%s) - start)) s"
