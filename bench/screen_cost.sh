#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Screen-space passes against the geometry pass at 1920x1080 on the README's street
# view, for two builds in the same run, interleaved A B B A A B ... (issue 15): per pass the
# median over the rounds of each round's median of 5 frames, and the ratio of all
# screen-space passes together to the geometry pass. The geometry pass is GL_POINTS
# (`--raster points`): the pass-cost ratio stays measured against it (issue 20).
# usage: bench/screen_cost.sh BUILD_A BUILD_B [SCENE.strata] [ROUNDS]
#   (BUILD_*: release build folders, e.g. a build of main and build/release;
#    EXTRA_A / EXTRA_B: more strata-view options for one side, e.g. to compare settings;
#    CLOCK: cpu (default: the CPU time of the viewer's threads per pass, which other work
#    on a shared machine does not inflate) or wall; a build without --stats-clock times
#    wall clock; PER_ROUND: passes to list round by round as well, e.g. "hpr pullpush",
#    to pair the two builds' rounds)
set -euo pipefail
a=$1 b=$2
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
scene=${3:-$work/street2m.strata}
rounds=${4:-3}
if [ ! -f "$scene" ]; then
    "$b/src/strata-synth" street --points 2000000 --seed 1 -o "$work/street2m.las" --quiet
    "$b/preprocess/strata-convert" "$work/street2m.las" -o "$scene" --force -q
fi
camera=650235,5401873.6,105.5,180,-8,70
size=${SIZE:-1920x1080}
clock=${CLOCK:-cpu}
out=$(mktemp -d)
clock_option() {
    local help
    help=$("$1/src/strata-view" --help)
    if [[ $help == *--stats-clock* ]]; then
        echo "--stats-clock $clock"
    else
        echo "$1: no --stats-clock, wall clock" >&2
    fi
}
# The order alternates A B, B A, ...: the second run of a round read about 2 ms lower in
# HPR (issue 15's sixteenth round), so a fixed order biased B.
for round in $(seq "$rounds"); do
    order="a b"
    [ $((round % 2)) = 0 ] && order="b a"
    for side in $order; do
        bin=$a extra=${EXTRA_A:-}
        [ $side = b ] && bin=$b extra=${EXTRA_B:-}
        extra="$extra $(clock_option "$bin")"
        # shellcheck disable=SC2086 # EXTRA_*: several options
        "$bin/src/strata-view" --headless "$scene" --camera=$camera --size "$size" --repeat 5 \
            --stats --raster points --pipeline shaded $extra | grep '^median' >>"$out/$side"
    done
done
# "median of 5 frames: frame F ms, geometry G ms, unproject U ms, hpr H ms, ..."
for side in a b; do
    python3 - "$out/$side" "$side" <<'PY'
import re, statistics, sys
rows = [dict((k, float(v)) for k, v in re.findall(r'(\w+) ([0-9.]+) ms', l)) for l in open(sys.argv[1])]
keys = [k for k in rows[0] if k != 'frame']
med = {k: statistics.median(r[k] for r in rows) for k in keys}
screen = sum(v for k, v in med.items() if k != 'geometry')
spread = [sum(v for k, v in r.items() if k not in ('frame', 'geometry')) / r['geometry'] for r in rows]
print(sys.argv[2], ' '.join('%s %.1f' % (k, v) for k, v in med.items()),
      '| screen %.1f ms = %.2fx geometry (rounds %s)' % (screen, screen / med['geometry'],
      ', '.join('%.2f' % s for s in spread)))
PY
done
for pass in ${PER_ROUND:-}; do
    for side in a b; do
        echo "$side $pass per round: $(grep -o "$pass [0-9.]* ms" "$out/$side" | cut -d' ' -f2 |
            tr '\n' ' ')"
    done
done
rm -rf "$out"
