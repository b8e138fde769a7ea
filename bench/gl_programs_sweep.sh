#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Whether every shader program of strata-view compiles and links on this machine's GL
# driver: renders a small scene headless with each pipeline, method and option that
# selects its own programs, and prints the ones that fail with the driver's log. Meant for
# a new driver (a GPU machine: NVIDIA's compiler rejects GLSL that Mesa's accepts);
# the test suite covers llvmpipe.
#
#   bench/gl_programs_sweep.sh SCENE.strata [NORMALS_SCENE.strata]
#
# BIN=build folder or one folder holding the programs (default build/release).
# Exits 1 when any setting fails.
set -uo pipefail
cd "$(dirname "$0")/.."
[ $# -ge 1 ] || {
    sed -n '3,12p' "$0"
    exit 2
}
scene=$1
normals_scene=${2:-$1}
bin=${BIN:-build/release}
view=$bin/src/strata-view
[ -x "$view" ] || view=$bin/strata-view
settings=(
    "--pipeline raw" "--pipeline raw --raster points" "--pipeline raw --raster-32bit"
    "--pipeline raw --point-size 3" "--pipeline raw --point-size adaptive"
    "--pipeline hpr" "--pipeline fill" "--pipeline normals" "--pipeline shaded"
    "--pipeline edl" "--pipeline shaded --raster points" "--pipeline shaded --raster-32bit"
    "--hpr exhaustive" "--hpr pyramid" "--hpr katz" "--hpr-gaps blocks"
    "--normals ld" "--normals pd" "--normals pc" "--normals ti" "--normals pc --samples 25"
    "--smooth" "--normals-every-pixel" "--no-fill-classes none" "--hud"
    "--colour intensity" "--colour class" "--colour returns" "--colour height"
    "--pipeline splats --splat-method geometry" "--pipeline splats --splat-method instanced"
    "--pipeline splats --splat-method pulled"
)
failed=0
for s in "${settings[@]}"; do
    target=$scene
    case "$s" in *splats*) target=$normals_scene ;; esac
    # shellcheck disable=SC2086
    out=$("$view" --headless "$target" --size 320x240 --frames 3 --stats $s 2>&1)
    if [ $? -ne 0 ]; then
        failed=1
        echo "FAIL $s"
        echo "$out" | grep -v '^\(frame\|  gpu ms\)' | head -8 | sed 's/^/    /'
    else
        echo "ok   $s"
    fi
done
echo "$("$view" --headless "$scene" --size 64x64 --frames 1 --stats 2>&1 | grep '^renderer')"
exit $failed
