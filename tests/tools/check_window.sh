#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view in a real window (Xvfb, GLFW, llvmpipe), driven as a person would:
#  1. a window resized from 640x360 to 800x600 shows exactly what a fresh 800x600
#     window shows (same camera, fully loaded);
#  2. once everything is loaded and nothing moves, the viewer sleeps: under 5 % of one
#     core over 3 s (it redrew at about 5 fps, ~170 % CPU, before);
#  3. a key press wakes it up again (the title switches to fly mode);
#  4. + and Z change the point size, shown in the title, and the picture.
# usage: check_window.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
mkdir -p "$work"
# shellcheck source=window_session.sh
source "$(dirname "$0")/window_session.sh"
window_session_start 90
window_scene street "street --points 300000 --seed 2"
camera=650235,5401873.6,105.5,180,-8,70

start_viewer() { # WxH
    # No readout: its frames-per-second figure differs from window to window.
    "$bin/src/strata-view" "$work/street.strata" --camera=$camera --size "$1" --pipeline raw \
        --no-readout >"$work/viewer.log" 2>&1 &
    viewer=$!
    find_window
}

start_viewer 640x360
settle
xdotool windowsize "$win" 800 600
settle
cp "$work/now.raw" "$work/resized.raw"

# Idle: CPU seconds used over 3 s of nothing happening.
ticks() { awk '{ print $14 + $15 }' "/proc/$viewer/stat"; }
t0=$(ticks)
sleep 3
t1=$(ticks)
hz=$(getconf CLK_TCK)
idle_pct=$(( (t1 - t0) * 100 / (3 * hz) ))
echo "idle CPU: $((t1 - t0)) ticks in 3 s ($idle_pct % of one core)"
[ "$idle_pct" -lt 5 ] || { echo "the viewer does not sleep when idle" >&2; exit 1; }

# A key wakes it: F switches to fly mode, shown in the title.
xdotool key --window "$win" f
for i in $(seq 1 30); do
    sleep 0.5
    title=$(xdotool getwindowname "$win")
    [[ $title == *"[fly"* ]] && break
done
echo "title after F: $title"
[[ $title == *"[fly"* ]] || { echo "the title does not show fly mode" >&2; exit 1; }

# Point size (raw pipeline): + widens the points, Z makes them adaptive; the title says
# so and the picture changes (the camera has not moved since the resize).
wait_title() { # TEXT
    for i in $(seq 1 30); do
        title=$(xdotool getwindowname "$win")
        [[ $title == *"$1"* ]] && return 0
        sleep 0.5
    done
    echo "the title does not show '$1': $title" >&2
    exit 1
}
xdotool key --window "$win" equal
wait_title "[raw, points 2 px]"
settle
cmp -s "$work/now.raw" "$work/resized.raw" && { echo "2 px points look like 1 px ones" >&2; exit 1; }
xdotool key --window "$win" z
wait_title "[raw, points adaptive 1-8 px]"
echo "title after + and Z: $title"
kill "$viewer"
wait "$viewer" 2>/dev/null || true

start_viewer 800x600
settle
cp "$work/now.raw" "$work/fresh.raw"
kill "$viewer"
wait "$viewer" 2>/dev/null || true
viewer=
if ! cmp -s "$work/resized.raw" "$work/fresh.raw"; then
    python3 - "$work/resized.raw" "$work/fresh.raw" <<'PY'
import sys
a, b = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read()
diff = sum(1 for i in range(0, min(len(a), len(b)), 4) if a[i:i + 3] != b[i:i + 3])
print(f"resized and fresh windows differ in {diff} of {len(b) // 4} pixels", file=sys.stderr)
PY
    exit 1
fi
echo "a resized window shows the same picture as a fresh one of that size"
