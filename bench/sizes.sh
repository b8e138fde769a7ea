#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Frame time at a 30 M-point budget against scene size (issue 6): the same elevated view
# down a strata-synth street (seed 7) of 1 M, 10 M, 100 M points and the largest
# converted, 1920x1080, raw and shaded, median of 3 frames of the loaded view.
# usage: bench/sizes.sh LARGEST.strata   (makes the smaller scenes in $BENCH_DIR)
set -euo pipefail
cd "$(dirname "$0")/.."
largest=$1
bin=build/release
[ -x $bin/src/strata-view ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
scenes=()
for n in 1000000 10000000 100000000; do
    s="$work/street-$n-seed7.strata"
    if [ ! -f "$s" ]; then
        $bin/src/strata-synth street --points $n --seed 7 -o "$work/tmp.las" --quiet
        $bin/preprocess/strata-convert "$work/tmp.las" -o "$s" --force -q
        rm -f "$work/tmp.las"
    fi
    scenes+=("$s")
done
scenes+=("$largest")
camera=${CAMERA:-650200,5401873.6,140,0,-20,70} # 35 m up behind the start, looking down the street
for s in "${scenes[@]}"; do
    echo "== $(basename "$s"): $($bin/src/strata-info "$s" | grep '^points' | tr -s ' ')"
    for pipeline in raw shaded; do
        printf '  %-7s' "$pipeline"
        $bin/src/strata-view --headless "$s" --camera=$camera --size 1920x1080 \
            --budget 30000000 --gpu-mem 2048 --pipeline $pipeline --repeat 3 --stats |
            grep median | sed 's/median of 3 frames: //'
    done
done
