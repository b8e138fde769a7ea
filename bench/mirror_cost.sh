#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Cost of the mirror pass (issue 13, docs/MIRRORS.md): the frame with the room's
# mirrors drawn by reflection against the same frame without (--no-reflections; ghosts
# hidden in both), strata-synth mirror (POINTS, default 5 M) seen from inside towards
# the east-wall mirror, 1920x1080, raw and with a screen-space pipeline. Runs alternate
# A B A B ... (ROUNDS pairs); each run prints the median of REPEAT frames of a fully
# loaded view; the table gives the median over the rounds and the median of the
# per-pair ratios B / A.
# usage: bench/mirror_cost.sh       (POINTS=5000000 ROUNDS=5 REPEAT=9 SIZE=1920x1080)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
points=${POINTS:-5000000}
rounds=${ROUNDS:-5}
repeat=${REPEAT:-9}
size=${SIZE:-1920x1080}
scene=$work/room$points.strata
if [ ! -f "$scene" ]; then
    "$bin"/src/strata-synth mirror --points "$points" --origin utm -o "$work/room$points.las" --quiet
    "$bin"/preprocess/strata-convert "$work/room$points.las" -o "$scene" --force -q \
        --mirrors "$work/room$points.mirrors.json"
    rm -f "$work/room$points.las"
fi
mirrors=$work/room$points.mirrors.json
# 5 m into the room, looking east at the 2 x 1.8 m mirror (UTM origin of strata-synth).
camera=650246.375,5401877.625,104.85,0,0,75

run() { # PIPELINE [options] -> frame ms (median of REPEAT)
    "$bin"/src/strata-view --headless "$scene" --mirrors "$mirrors" --camera=$camera \
        --size "$size" --pipeline "$1" --repeat "$repeat" --out "$work/mirror_cost.png" "${@:2}" |
        sed -n 's/^median of [0-9]* frames: frame \([0-9.]*\) ms.*/\1/p'
}
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }

printf '%-9s %12s %12s %14s %s\n' pipeline without_ms with_ms ratio pairs
for pipeline in raw shaded; do
    : >"$work/mirror_cost.$pipeline"
    for _ in $(seq "$rounds"); do
        a=$(run "$pipeline" --no-reflections)
        b=$(run "$pipeline")
        echo "$a $b" >>"$work/mirror_cost.$pipeline"
    done
    without=$(awk '{ print $1 }' "$work/mirror_cost.$pipeline" | median)
    with=$(awk '{ print $2 }' "$work/mirror_cost.$pipeline" | median)
    ratio=$(awk '{ print $2 / $1 }' "$work/mirror_cost.$pipeline" | median)
    pairs=$(awk '{ printf "%.2f ", $2 / $1 }' "$work/mirror_cost.$pipeline")
    printf '%-9s %12s %12s %14.3f %s\n' "$pipeline" "$without" "$with" "$ratio" "$pairs"
done
