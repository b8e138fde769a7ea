#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-view's splat keys in a real window (Xvfb, GLFW, llvmpipe), on a street converted
# with --normals: O switches the points (raw) to splats and the picture changes; ] grows
# the splats (the picture changes again, stderr says "splat scale 1.25"); [ brings them
# back to the scale-1 picture exactly; O again returns to the first picture exactly.
# usage: check_window_splats.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
mkdir -p "$work"
# shellcheck source=window_session.sh
source "$(dirname "$0")/window_session.sh"
window_session_start 900
window_scene street "street --points 200000 --seed 3" --normals
camera=650235,5401873.6,105.5,180,-8,70
"$bin/src/strata-view" "$work/street.strata" --camera=$camera --size 400x300 --pipeline raw \
    --no-readout >"$work/viewer.log" 2>&1 &
viewer=$!
find_window
settle
cp "$work/now.raw" "$work/points.raw"
press() { # KEY: presses it and waits for the picture to settle
    xdotool key --window "$win" "$1"
    sleep 0.5
    settle
}
press o
cp "$work/now.raw" "$work/splats.raw"
press bracketright
cp "$work/now.raw" "$work/bigger.raw"
press bracketleft
cp "$work/now.raw" "$work/back.raw"
press o
cp "$work/now.raw" "$work/points_again.raw"
kill "$viewer"
wait "$viewer" 2>/dev/null || true
viewer=
fail() { echo "$1 (log: $work/viewer.log)" >&2; exit 1; }
! cmp -s "$work/points.raw" "$work/splats.raw" || fail "O did not change the picture"
! cmp -s "$work/splats.raw" "$work/bigger.raw" || fail "] did not change the picture"
cmp -s "$work/splats.raw" "$work/back.raw" || fail "[ did not return to the scale-1 splats"
cmp -s "$work/points.raw" "$work/points_again.raw" || fail "O twice did not return to points"
grep -q "pipeline splats" "$work/viewer.log" || fail "no 'pipeline splats' on stderr"
grep -q "splat scale 1.25" "$work/viewer.log" || fail "no 'splat scale 1.25' on stderr"
echo "O, ] and [ switch and scale the splats in the window"
