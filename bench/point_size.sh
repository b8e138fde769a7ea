#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Point size (issue 18): time against image error. Part 1, image error: strata-bench on
# the synthetic street (1.5 M points, its truth sidecar) from STREET street-level views,
# raw pipeline, each point size; surface_error is the fraction of pixels whose depth
# disagrees with the true surface (holes + see-through + bleed, docs/BENCH.md). Part 2,
# time: the geometry pass of strata-view at the demo camera, both rasterisers and every
# size, runs interleaved (round r runs every method and size once, ROUNDS rounds), each
# run the median of REPEAT frames of the loaded view; the table gives the median over
# the rounds and the ratio to one pixel with the same rasteriser.
# usage: bench/point_size.sh   (SIZES="1 2 3 5 adaptive" ROUNDS=3 REPEAT=5 STREET=4
#                               SIZE=960x540; ERRORS=0 skips part 1)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
[ -x $bin/src/strata-view ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
sizes=${SIZES:-"1 2 3 5 adaptive"}
rounds=${ROUNDS:-3}
repeat=${REPEAT:-5}
street=${STREET:-4}
size=${SIZE:-960x540}
camera=650235,5401873.6,105.5,180,-8,70 # the demo camera (scripts/demo.sh)
scene=$work/street_ps.strata
if [ ! -f "$scene" ]; then
    $bin/src/strata-synth street --points 1500000 --seed 1 -o "$work/street_ps.las" --quiet
    $bin/preprocess/strata-convert "$work/street_ps.las" -o "$scene" --force -q
    rm -f "$work/street_ps.las"
fi

# Part 1: errors (and strata-bench's own times, not interleaved) per size.
if [ "${ERRORS:-1}" != 0 ]; then
list=$(echo "$sizes" | tr ' ' ',')
$bin/src/bench/strata-bench "$scene" --street "$street" --size "$size" --pipelines raw \
    --point-sizes "$list" --repeat "$repeat" --no-image-error --quiet --out "$work/point_size" >/dev/null
python3 - "$work/point_size/results.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print("%-18s %8s %8s %8s %8s %8s" % ("setting", "error", "hole", "see-thr", "bleed", "geom_ms"))
for setting in dict.fromkeys(r["setting"] for r in rows):
    rs = [r for r in rows if r["setting"] == setting]
    mean = lambda k: statistics.mean(float(r[k]) for r in rs)
    print("%-18s %8.3f %8.3f %8.3f %8.3f %8.1f" % (setting, mean("surface_error"), mean("surface_hole"),
          mean("surface_see_through"), mean("surface_bleed"), statistics.median(float(r["geometry_ms"]) for r in rs)))
print("(means over %d street views; geometry_ms: median over the views, not interleaved)" % len({r["camera"] for r in rows}))
PY
fi

# Part 2: interleaved geometry-pass times.
run() {
    $bin/src/strata-view --headless "$scene" --camera=$camera --size "$size" --raster "$1" \
        --pipeline raw --point-size "$2" --repeat "$repeat" --stats | grep -E '^(median|renderer)'
}
median() { sort -g | awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
field() { sed -n "s/.*$1 \([0-9.]*\) ms.*/\1/p"; }
log=$work/point_size_log.txt
: >"$log"
for ((r = 0; r < rounds; r++)); do
    for method in compute points; do
        for s in $sizes; do
            echo "== $method $s round $r $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$log"
            run $method "$s" >>"$log"
        done
    done
done
printf '%-9s %-9s %12s %8s   %s\n' raster size geometry_ms ratio "all rounds (ms)"
for method in compute points; do
    base=
    for s in $sizes; do
        all=$(awk -v m="$method" -v s="$s" '/^==/ { on = ($2 == m && $3 == s) } on && /^median/' "$log" | field geometry)
        med=$(echo "$all" | median)
        base=${base:-$med}
        printf '%-9s %-9s %12s %8.2f   %s\n' $method "$s" "$med" "$(echo "$med / $base" | bc -l)" "$(echo $all)"
    done
done
grep -m1 '^renderer' "$log" || true
echo "(every run: $log)"
