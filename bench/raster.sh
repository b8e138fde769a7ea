#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The geometry pass's two rasterisers (issue 20): GL_POINTS against the compute
# rasteriser at about 1 M, 5 M and 30 M drawn points, 1920x1080, then the whole shaded
# frame (geometry and every screen-space pass) with each. Runs alternate A B A B ...
# (ROUNDS rounds); each run prints the median of REPEAT frames of a fully loaded view;
# the table gives the median over the rounds of the wall time and of the process's CPU
# time (all threads: on llvmpipe the rasteriser's work, steady on a busy machine), and
# the ratios GL_POINTS / compute. With BEFORE=<build dir of an older strata-view> its
# compute rasteriser runs in every round too ("before"), for the change's own ratio.
# SIZES are scene sizes (strata-synth street); with --min-spacing 0.1 the demo camera
# draws 0.97 M, 4.9 M and 31 M of 1 M, 5.2 M and 40 M.
# usage: bench/raster.sh   (SIZES="1000000 5200000 40000000" ROUNDS=3 REPEAT=5
#                           PIPELINES="raw shaded" BEFORE= BENCH_DIR=/tmp/strata-bench)
#   On a GPU machine: the same command; EGL picks the NVIDIA driver when it is installed
#   (check the "renderer" line). BENCH_DIR holds the scenes (about 1.2 GB for 30 M).
#   The CPU times mean nothing there (the GPU does the work): read the wall times.
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
pipelines=${PIPELINES:-"raw shaded"}
before=${BEFORE:-}
methods="points compute"
[ -n "$before" ] && methods="points compute before"
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

# run SCENE METHOD PIPELINE N -> the "median", "cpu median" and "renderer" lines
run() {
    local budget=$(($4 + $4 / 2)) exe=$bin raster=$2
    [ "$2" = before ] && exe=$before && raster=compute
    $exe/src/strata-view --headless "$1" --camera=$camera --size "$size" --raster "$raster" \
        --pipeline "$3" --budget "$budget" --gpu-mem 8192 --min-spacing 0.1 \
        --repeat "$repeat" --stats |
        grep -E '^(median|cpu median|renderer)'
}

echo "== $(date -u +%FT%TZ) sizes $sizes rounds $rounds repeat $repeat methods $methods" >>"$work/raster_log.txt"
for n in $sizes; do
    scene=$(scene_of "$n")
    for pipeline in $pipelines; do
        for method in $methods; do : >"$work/raster_$method.txt"; done
        for ((r = 0; r < rounds; r++)); do
            for method in $methods; do
                run "$scene" $method $pipeline "$n" >>"$work/raster_$method.txt"
            done
        done
        for method in $methods; do
            echo "== $n $pipeline $method $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)" >>"$work/raster_log.txt"
            cat "$work/raster_$method.txt" >>"$work/raster_log.txt"
        done
        python3 - "$work" "$n" "$pipeline" $methods <<'PY'
import re, statistics, sys
work, n, pipeline, methods = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
what = 'geometry' if pipeline == 'raw' else 'frame'
def runs(method, prefix):
    lines = [l for l in open('%s/raster_%s.txt' % (work, method)) if l.startswith(prefix)]
    return [dict((k, float(v)) for k, v in re.findall(r'(\w+) ([0-9.]+) ms', l)) for l in lines]
wall = {m: runs(m, 'median') for m in methods}
cpu = {m: runs(m, 'cpu median') for m in methods}
med = lambda rows, key: statistics.median(r[key] for r in rows) if rows and key in rows[0] else float('nan')
drawn = re.findall(r'; ([0-9]+) points drawn', open('%s/raster_compute.txt' % work).read())
print('%s points (%s drawn), %s, %s: median over %d rounds, ms' %
      (n, drawn[-1] if drawn else '?', pipeline, what, len(wall['compute'])))
for m in methods:
    rounds = ', '.join('%.0f' % r[what] for r in wall[m])
    print('  %-8s wall %8.1f (rounds %s)  cpu %8.1f' % (m, med(wall[m], what), rounds, med(cpu[m], what)))
for m in methods[1:]:
    print('  points / %s: wall %.2fx, cpu %.2fx' % (m, med(wall['points'], what) / med(wall[m], what),
                                                  med(cpu['points'], what) / med(cpu[m], what)))
if 'before' in methods:
    print('  before / compute: wall %.2fx, cpu %.2fx' % (med(wall['before'], what) / med(wall['compute'], what),
                                                       med(cpu['before'], what) / med(cpu['compute'], what)))
if pipeline != 'raw':
    for m in methods:
        keys = [k for k in wall[m][0] if k not in ('frame',)] + ['frame']
        print('  %-8s composition (wall medians): %s' % (m, ' '.join('%s %.0f' % (k, med(wall[m], k)) for k in keys)))
PY
    done
done
grep -m1 '^renderer' "$work/raster_compute.txt" || true
echo "(every run: $work/raster_log.txt)"
