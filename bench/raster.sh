#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The geometry pass's two rasterisers (issue 20): GL_POINTS against the compute
# rasteriser at about 1 M, 5 M and 30 M drawn points, 1920x1080, then the whole shaded
# frame (geometry and every screen-space pass) with each. Runs alternate A B A B ...
# (ROUNDS pairs); each run prints the median of REPEAT frames of a fully loaded view; the
# table gives the median over the rounds and the ratio GL_POINTS / compute.
# SIZES are scene sizes (strata-synth street); with --min-spacing 0.1 the demo camera
# draws 0.97 M, 5.0 M and 31 M of 1 M, 5.2 M and 40 M.
# usage: bench/raster.sh            (SIZES="1000000 5200000 40000000" ROUNDS=3 REPEAT=5)
#   On a GPU machine: the same command; EGL picks the NVIDIA driver when it is installed
#   (check the "renderer" line). BENCH_DIR holds the scenes (about 1.2 GB for 30 M).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
[ -x $bin/src/strata-view ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
sizes=${SIZES:-"1000000 5200000 40000000"}
rounds=${ROUNDS:-3}
repeat=${REPEAT:-5}
size=${SIZE:-1920x1080}
# The street seen along its length: the demo camera (scripts/demo.sh); the budget is
# the whole scene and the LOD cut refines down to 0.1 px spacing, so nearly every point
# in view is drawn (many per pixel: the rasteriser's load, not a sensible view).
camera=650235,5401873.6,105.5,180,-8,70

scene_of() {
    local n=$1 scene=$work/street$1.strata
    if [ ! -f "$scene" ]; then
        $bin/src/strata-synth street --points "$n" --seed 1 -o "$work/street$n.las" --quiet
        $bin/preprocess/strata-convert "$work/street$n.las" -o "$scene" --force -q
        rm -f "$work/street$n.las"
    fi
    echo "$scene"
}

# run SCENE METHOD PIPELINE N -> "frame geometry [pass ms...]" from the median line
run() {
    local budget=$(($4 + $4 / 2))
    $bin/src/strata-view --headless "$1" --camera=$camera --size "$size" --raster "$2" \
        --pipeline "$3" --budget "$budget" --gpu-mem 8192 --min-spacing 0.1 \
        --repeat "$repeat" --stats |
        grep -E '^(median|renderer)'
}

median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
field() { sed -n "s/.*$1 \([0-9.]*\) ms.*/\1/p"; }

printf '%-10s %-8s %12s %12s %12s %8s\n' scene pipeline points_ms compute_ms drawn_pts ratio
for n in $sizes; do
    scene=$(scene_of "$n")
    for pipeline in raw shaded; do
        : >"$work/raster_points.txt"
        : >"$work/raster_compute.txt"
        for ((r = 0; r < rounds; r++)); do
            for method in points compute; do
                run "$scene" $method $pipeline "$n" >>"$work/raster_$method.txt"
            done
        done
        for method in points compute; do
            echo "== $n $pipeline $method $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$work/raster_log.txt"
            cat "$work/raster_$method.txt" >>"$work/raster_log.txt"
        done
        what=geometry
        [ $pipeline = shaded ] && what=frame
        a=$(field "$what" <"$work/raster_points.txt" | median)
        b=$(field "$what" <"$work/raster_compute.txt" | median)
        drawn=$(sed -n 's/.*; \([0-9]*\) points drawn.*/\1/p' "$work/raster_compute.txt" | tail -1)
        printf '%-10s %-8s %12s %12s %12s %8.2f\n' "$n" "$pipeline/$what" "$a" "$b" "$drawn" \
            "$(echo "$a / $b" | bc -l)"
        if [ $pipeline = shaded ]; then
            for method in points compute; do
                printf '  %-8s composition (medians):' $method
                for pass in geometry unproject hpr pullpush normals shade frame; do
                    printf ' %s %s' $pass "$(field "$pass" <"$work/raster_$method.txt" | median)"
                done
                echo
            done
        fi
    done
done
grep -m1 '^renderer' "$work/raster_log.txt" || true
echo "(every run: $work/raster_log.txt)"
