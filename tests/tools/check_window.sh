#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view in a real window (Xvfb, GLFW, llvmpipe), driven as a person would:
#  1. a window resized from 640x360 to 800x600 shows exactly what a fresh 800x600
#     window shows (same camera, fully loaded);
#  2. once everything is loaded and nothing moves, the viewer sleeps: under 5 % of one
#     core over 3 s (it redrew at about 5 fps, ~170 % CPU, before);
#  3. a key press wakes it up again (the title switches to fly mode).
# usage: check_window.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
mkdir -p "$work"
for tool in Xvfb xdotool xwd; do
    command -v $tool >/dev/null || { echo "$tool is missing (scripts/install-deps.sh installs it)" >&2; exit 1; }
done
display=:$((90 + RANDOM % 400))
Xvfb "$display" -screen 0 1280x1024x24 -nolisten tcp >/dev/null 2>&1 &
xvfb=$!
viewer=
cleanup() {
    [ -n "$viewer" ] && kill "$viewer" 2>/dev/null || true
    kill "$xvfb" 2>/dev/null || true
}
trap cleanup EXIT
export DISPLAY=$display
sleep 1
"$bin/src/strata-synth" street --points 300000 --seed 2 -o "$work/street.las" --quiet
"$bin/preprocess/strata-convert" "$work/street.las" -o "$work/street.strata" --force -q
camera=650235,5401873.6,105.5,180,-8,70

# Pixels of the window (xwd without its header and colour map), in a file.
pixels() {
    xwd -id "$1" -silent >"$work/shot.xwd"
    python3 - "$work/shot.xwd" "$2" <<'PY'
import struct, sys
d = open(sys.argv[1], "rb").read()
f = struct.unpack(">25I", d[:100])
start = f[0] + f[19] * 12  # header size + colour map entries
open(sys.argv[2], "wb").write(d[start:start + f[12] * f[5]])
PY
}

# Waits until the window's picture is the same three times in a row, 1 s apart (a busy
# machine can pause the loader for a second).
settle() {
    local previous="" same=0 i
    for i in $(seq 1 120); do
        sleep 1
        pixels "$1" "$work/now.raw"
        local sum
        sum=$(sha256sum <"$work/now.raw")
        if [ "$sum" = "$previous" ]; then
            same=$((same + 1))
            [ $same -ge 2 ] && return 0
        else
            same=0
        fi
        previous=$sum
    done
    echo "the window never settled" >&2
    exit 1
}

start_viewer() { # WxH
    # No readout: its frames-per-second figure differs from window to window.
    "$bin/src/strata-view" "$work/street.strata" --camera=$camera --size "$1" --pipeline raw \
        --no-readout >"$work/viewer.log" 2>&1 &
    viewer=$!
    local i
    for i in $(seq 1 60); do
        win=$(xdotool search --pid "$viewer" 2>/dev/null | head -1 || true)
        [ -n "$win" ] && return 0
        sleep 0.5
    done
    echo "no window appeared" >&2
    cat "$work/viewer.log" >&2
    exit 1
}

start_viewer 640x360
settle "$win"
xdotool windowsize "$win" 800 600
settle "$win"
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
kill "$viewer"
wait "$viewer" 2>/dev/null || true

start_viewer 800x600
settle "$win"
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
