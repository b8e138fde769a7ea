#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view's mirror tool in a real window (Xvfb, GLFW, llvmpipe), driven with
# xdotool: O turns the tool on, three Ctrl+clicks on the room's back wall and one on
# the floor, Backspace drops the floor's, Enter closes the outline; the mirror file then
# holds one mirror of three vertices on the wall plane (x = 12), its front towards the
# camera. Then the scene with its ghosts: V shows them, and the picture changes.
# usage: check_window_mirror.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$(cd "$1" && pwd) work=$2
mkdir -p "$work"
# shellcheck source=window_session.sh
source "$(dirname "$0")/window_session.sh"
window_session_start 900
window_scene room "mirror --points 600000 --origin zero" --mirrors "$work/room.mirrors.json"
rm -f "$work/mirrors.json"
(cd "$work" && exec "$bin/src/strata-view" "$work/room.strata" --camera=5,4,1.6,0,0,75 \
    --size 640x400 --pipeline raw >"$work/viewer.log" 2>&1) &
viewer=$!
find_window
settle
xdotool key --window "$win" b
picks() { grep -c '^pick: x ' "$work/viewer.log" || true; }
for point in "395 160" "455 160" "455 240" "300 330"; do
    # A loaded machine may still be drawing the cut, or be slow to answer: wait up to
    # 5 s for each click's pick, and click again only when none came (a miss).
    before=$(picks)
    for _ in $(seq 1 10); do
        # shellcheck disable=SC2086
        xdotool mousemove --window "$win" $point
        xdotool keydown ctrl click 1 keyup ctrl
        for _ in $(seq 1 10); do
            sleep 0.5
            [ "$(picks)" -gt "$before" ] && break 2
        done
    done
done
[ "$(picks)" = 4 ] || { cat "$work/viewer.log" >&2; exit 1; }
xdotool key --window "$win" BackSpace
sleep 0.5
xdotool key --window "$win" Return
sleep 1
window_pixels "$work/hidden.rgb"
xdotool key --window "$win" v
sleep 1
settle
window_pixels "$work/shown.rgb"
kill "$viewer"; wait "$viewer" 2>/dev/null || true; viewer=
grep -q "mirror ghosts shown" "$work/viewer.log" || { cat "$work/viewer.log" >&2; exit 1; }
cmp -s "$work/hidden.rgb" "$work/shown.rgb" && { echo "V changed nothing" >&2; exit 1; }
[ -f "$work/mirrors.json" ] || { cat "$work/viewer.log" >&2; exit 1; }
python3 - "$work/mirrors.json" <<'PY'
import json, sys
f = json.load(open(sys.argv[1]))
m = f["mirrors"]
assert f["format"] == "strata-mirrors" and len(m) == 1 and len(m[0]["polygon"]) == 3, f
xs = [v[0] for v in m[0]["polygon"]]
assert all(abs(x - 12.0) < 0.05 for x in xs), xs  # on the east wall
a, b, c = m[0]["polygon"]
u = [b[i] - a[i] for i in range(3)]
v = [c[i] - a[i] for i in range(3)]
nx = u[1] * v[2] - u[2] * v[1]
assert nx < 0, nx  # front towards the camera (west of the wall)
print("window mirror tool: one mirror of 3 vertices on the wall, front towards the camera")
PY
