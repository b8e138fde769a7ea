#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Cost of every screen-space pass at 1920x1080 next to the geometry pass (issue 5), on a
# strata-synth street view: median of 5 frames of a fully loaded view, per pass, for
# each normal method and for pyramidal against exhaustive HPR.
# usage: bench/passes.sh [SCENE.strata] (default: a 2 M-point street made here)
#   CLOCK=cpu: per-pass CPU time of the viewer's threads (strata-view --stats-clock;
#   steady on a shared machine) instead of wall time
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/release
[ -x $bin/src/strata-view ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
scene=${1:-$work/street2m.strata}
if [ ! -f "$scene" ]; then
    $bin/src/strata-synth street --points 2000000 --seed 1 -o "$work/street2m.las" --quiet
    $bin/preprocess/strata-convert "$work/street2m.las" -o "$scene" --force -q
fi
camera=650235,5401873.6,105.5,180,-8,70
size=${SIZE:-1920x1080}
run() {
    printf '%-34s ' "$*"
    # GL_POINTS: the pass costs stay measured against the same geometry pass (issue 20).
    $bin/src/strata-view --headless "$scene" --camera=$camera --size "$size" --repeat 5 --stats \
        --stats-clock "${CLOCK:-wall}" --raster points "$@" |
        grep median | sed 's/median of 5 frames: //'
}
run --pipeline raw
run --pipeline edl
run --pipeline shaded --normals pyramid
for method in ld pd pc ti; do
    for samples in 9 25; do
        [ $method = ld ] && [ $samples = 25 ] && continue
        run --pipeline normals --normals $method --samples $samples
    done
done
run --pipeline normals --normals ti --samples 9 --smooth
run --pipeline hpr --hpr pyramid
for radius in 4 8 16; do
    run --pipeline hpr --hpr exhaustive --hpr-radius $radius
done
