#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view's default view in a real window (Xvfb, GLFW, llvmpipe) after a resize:
#  1. a sphere framed in a 640x360 window, the window turned to 360x640: the same camera
#     now cuts the sphere at the left and right edges;
#  2. R frames the default view again for the window's new size: the sphere whole, clear
#     of the border band (issue 15, part 6), and the very picture a fresh 360x640 window
#     opens with.
# usage: check_window_home.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
mkdir -p "$work"
# shellcheck source=window_session.sh
source "$(dirname "$0")/window_session.sh"
window_session_start 2300
window_scene sphere "sphere --points 60000 --seed 3"

start_viewer() { # WxH
    "$bin/src/strata-view" "$work/sphere.strata" --size "$1" --pipeline raw --no-readout \
        >"$work/viewer.log" 2>&1 &
    viewer=$!
    find_window
}
stop_viewer() {
    kill "$viewer"
    wait "$viewer" 2>/dev/null || true
    viewer=
}
# The nearest point pixel (not black) to the window's border, in pixels, and the
# points' width over the window's: "MARGIN SPAN".
extent() { # RAW WIDTH HEIGHT
    python3 - "$@" <<'PY'
import sys
data, w, h = open(sys.argv[1], "rb").read(), int(sys.argv[2]), int(sys.argv[3])
xs, ys = [], []
for y in range(h):
    row = data[4 * w * y:4 * w * (y + 1)]
    for x in range(w):
        if row[4 * x] or row[4 * x + 1] or row[4 * x + 2]:
            xs.append(x)
            ys.append(y)
margin = min(min(xs), min(ys), w - 1 - max(xs), h - 1 - max(ys))
print(margin, "%.3f" % ((max(xs) - min(xs) + 1) / w))
PY
}

start_viewer 640x360
settle
read -r margin span < <(extent "$work/now.raw" 640 360)
echo "640x360: nearest point $margin px from the border, width span $span"
# The band at 360 px of height is 32 px, plus 8; framed on the root node's points, whose
# neighbours one level down may lie a few pixels farther out.
[ "$margin" -ge 36 ] || { echo "the default view is not clear of the border band" >&2; exit 1; }
xdotool windowsize "$win" 360 640
settle
read -r margin span < <(extent "$work/now.raw" 360 640)
echo "turned to 360x640: nearest point $margin px from the border, width span $span"
[ "$margin" -eq 0 ] || { echo "the old camera should cut the sphere in a narrow window" >&2; exit 1; }
xdotool key --window "$win" r
settle
cp "$work/now.raw" "$work/home.raw"
read -r margin span < <(extent "$work/home.raw" 360 640)
echo "after R: nearest point $margin px from the border, width span $span"
# The band at 640 px of height is 32 * 640 / 540 = 37.9 px, plus 8.
[ "$margin" -ge 42 ] || { echo "R does not frame the sphere whole for the new size" >&2; exit 1; }
python3 -c "import sys; sys.exit(0 if float('$span') > 0.6 else 1)" ||
    { echo "R frames the sphere too small" >&2; exit 1; }
stop_viewer

start_viewer 360x640
settle
stop_viewer
cmp -s "$work/now.raw" "$work/home.raw" ||
    { echo "R after a resize differs from a fresh window of that size" >&2; exit 1; }
echo "R after a resize frames the default view as a fresh window of that size does"
