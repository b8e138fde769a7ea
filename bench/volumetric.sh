#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Volumetric classes drawn as points (issue 15 part 5): what drawing them as points
# costs at SIZE, shaded pipeline, against the geometry pass and the frame. The mark is
# folded into the unproject pass (or the raster resolve) and the overlay into the shade
# pass, so there is no pass of its own to time. The table gives, per setting, the median
# over rounds of its frame and shade times less those of the same round's run with none
# ("+frame", "+shade"); the overlay's cost is in "+shade", the mark's (a few ms) in the
# unproject pass or the resolve. At 1080p on llvmpipe "+frame" is mostly noise. Scenes: the four lasR forest tiles (classes 1 and 2 only, so the canopy is
# --no-fill-classes 1) and the synthetic street at the demo camera (trees are classes
# 3-5, the default). Runs interleaved: each round runs A (points) then B (none) per
# scene, ROUNDS rounds; each run is the median of REPEAT frames of the loaded view;
# the table gives the median over the rounds.
# usage: bench/volumetric.sh   (ROUNDS=3 REPEAT=5 SIZE=1920x1080)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
rounds=${ROUNDS:-3}
repeat=${REPEAT:-5}
size=${SIZE:-1920x1080}
data=${STA_SHARED_DATA:-$(cd .. && pwd)/shared/data}
forest=$work/forest.strata
[ -f "$forest" ] || $bin/preprocess/strata-convert -q "$data"/laz-tiles/bcts_*.laz -o "$forest"
street=$work/street_vol.strata
if [ ! -f "$street" ]; then
    $bin/src/strata-synth street --points 1500000 --seed 1 -o "$work/street_vol.las" --quiet
    $bin/preprocess/strata-convert "$work/street_vol.las" -o "$street" --force -q
    rm -f "$work/street_vol.las"
fi
run() { # scene classes
    local view
    if [ "$1" = forest ]; then
        view=(--look=-60,-60,50,45,-30,40 --colour elevation)
        set -- "$forest" "$2"
    else
        view=(--camera=650235,5401873.6,105.5,180,-8,70)
        set -- "$street" "$2"
    fi
    $bin/src/strata-view --headless "$1" "${view[@]}" --size "$size" --pipeline shaded \
        --no-fill-classes "$2" --repeat "$repeat" --stats | grep -E '^median'
}
field() { sed -n "s/.*[ ,]$1 \([0-9.]*\) ms.*/\1/p"; }
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
log=$work/volumetric_log.txt
: >"$log"
for ((r = 0; r < rounds; r++)); do
    for scene in forest street; do
        a=$([ $scene = forest ] && echo 1 || echo 3-5)
        for classes in "$a" none; do
            echo "== $scene $classes round $r $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$log"
            run $scene "$classes" >>"$log"
        done
    done
done
printf '%-7s %-6s %9s %9s %9s %9s %11s %11s\n' scene fill frame_ms geom_ms shade_ms \
    "+frame_ms" "+shade_ms" "+shade/geom"
of_rounds() { # scene classes field -> that field of every round, one a line
    awk -v s="$1" -v c="$2" '/^==/ { on = ($2 == s && $3 == c) } on && /^median/' "$log" | field "$3"
}
extra() { # scene classes field -> the median over rounds of (field less none's field)
    paste <(of_rounds "$1" "$2" "$3") <(of_rounds "$1" none "$3") | awk '{ print $1 - $2 }' | median
}
for scene in forest street; do
    a=$([ $scene = forest ] && echo 1 || echo 3-5)
    for classes in "$a" none; do
        frame=$(of_rounds $scene "$classes" frame | median)
        geom=$(of_rounds $scene "$classes" geometry | median)
        shade=$(of_rounds $scene "$classes" shade | median)
        dshade=$(extra $scene "$classes" shade)
        printf '%-7s %-6s %9s %9s %9s %9.1f %11.1f %11.2f\n' $scene "$classes" "$frame" "$geom" \
            "$shade" "$(extra $scene "$classes" frame)" "$dshade" "$(echo "$dshade / $geom" | bc -l)"
    done
done
echo "(every run: $log)"
