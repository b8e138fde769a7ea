#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view's surveyor tools in a real window (Xvfb, GLFW, llvmpipe), driven with
# xdotool: F6 hides buildings, T selects the distance tool, two Ctrl+clicks measure,
# J saves the measurement; the JSON file holds the two picked points and their
# distance, the log names the picks, and the readout is drawn over the frame (the
# window's top-left corner differs from a --no-readout window's).
# usage: check_window_survey.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$(cd "$1" && pwd) work=$2
mkdir -p "$work"
# shellcheck source=window_session.sh
source "$(dirname "$0")/window_session.sh"
window_session_start 500
window_scene street "street --points 300000 --seed 1"
camera=650235,5401873.6,105.5,180,-8,70
rm -f "$work/m.json"

start_viewer() { # extra options
    (cd "$work" && exec "$bin/src/strata-view" "$work/street.strata" --camera=$camera --size 640x360 \
        --pipeline raw --colour class "$@" >"$work/viewer.log" 2>&1) &
    viewer=$!
    find_window
    settle
}

# The top-left 300x60 pixels of the window (where the readout goes).
corner() {
    xwd -id "$win" -silent >"$work/shot.xwd"
    python3 - "$work/shot.xwd" <<'PY'
import hashlib, struct, sys
d = open(sys.argv[1], "rb").read()
f = struct.unpack(">25I", d[:100])
start, stride = f[0] + f[19] * 12, f[12]
print(hashlib.sha256(b"".join(d[start + y * stride:start + y * stride + 300 * 4] for y in range(60))).hexdigest())
PY
}

start_viewer --no-readout
plain=$(corner)
kill "$viewer"; wait "$viewer" 2>/dev/null || true; viewer=

start_viewer --measure m.json
[ "$(corner)" != "$plain" ] || { echo "no readout over the frame" >&2; exit 1; }
xdotool key --window "$win" F6
sleep 1
settle
xdotool key --window "$win" t
picks=0
for point in "240 200" "400 250"; do
    # A loaded machine may still be drawing the cut: click again until a point is hit.
    for _ in $(seq 1 15); do
        # shellcheck disable=SC2086
        xdotool mousemove --window "$win" $point
        xdotool keydown ctrl click 1 keyup ctrl
        sleep 1
        [ "$(grep -c '^pick: x ' "$work/viewer.log" || true)" -gt $picks ] && break
        sleep 1
    done
    picks=$((picks + 1))
done
xdotool key --window "$win" j
sleep 2
kill "$viewer"; wait "$viewer" 2>/dev/null || true; viewer=
grep -q "class 6 (building) hidden" "$work/viewer.log" || { cat "$work/viewer.log" >&2; exit 1; }
[ "$(grep -c '^pick: x ' "$work/viewer.log")" = 2 ] || { cat "$work/viewer.log" >&2; exit 1; }
python3 - "$work/m.json" <<'PY'
import json, math, sys
m = json.load(open(sys.argv[1]))["measurements"]
assert len(m) == 1 and m[0]["kind"] == "distance" and len(m[0]["points"]) == 2, m
a, b = m[0]["points"]
d = math.dist(a, b)
assert abs(m[0]["values"]["distance_3d"] - d) < 1e-9 and d > 0.5, (d, m)
print("window survey: distance %.3f m between two picks, saved" % d)
PY
