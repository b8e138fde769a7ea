#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The whole benchmark report on a fresh machine (docs/BENCH.md): builds the release preset,
# makes synthetic scenes with known truth (sphere, planes, nested, the Stanford bunny mesh
# when ../shared/data has it, a street scan), converts them, runs strata-bench sweeps and
# draws PNG plots with gnuplot:
#   time_vs_error.png   per method, one point per setting: pass time against error
#   frame_vs_size.png   frame time against scene size at a fixed budget
#   error_vs_budget.png error against the point budget
# Default sizes are modest (a few minutes on 2 cores with llvmpipe);
# STRATA_BENCH_FULL=1 runs the full-size report (1920x1080, millions of points: hours).
# usage: bench/report.sh   (env: BENCH_DIR scratch, BENCH_OUT results and plots, BENCH_BUILD)
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
work=${BENCH_DIR:-/tmp/strata-report}
out=${BENCH_OUT:-$repo/build/bench-report}
mkdir -p "$work" "$out"

if [ "${STRATA_BENCH_FULL:-0}" = 1 ]; then
    size=1920x1080 views=8 repeat=5 analytic=2000000 street_sizes="2M 5M 10M 20M"
    budgets=1M,3M,10M,30M size_budget=3M street_points=20M katz_size=960x540
else
    size=480x270 views=2 repeat=2 analytic=200000 street_sizes="250k 500k 1M 2M"
    budgets=100k,200k,400k,700k,all size_budget=200k street_points=1M katz_size=240x135
fi

if ! command -v gnuplot >/dev/null; then
    echo "installing gnuplot-nox" >&2
    sudo=""
    [ "$(id -u)" = 0 ] || sudo=sudo
    $sudo apt-get update -qq && $sudo apt-get install -y -qq gnuplot-nox >/dev/null
fi

# BENCH_BUILD: another (Release) build folder instead of the release preset's.
bin=${BENCH_BUILD:-build/release}
if [ -n "${BENCH_BUILD:-}" ]; then
    cmake -S . -B "$bin" -DCMAKE_BUILD_TYPE=Release >/dev/null
else
    cmake --preset release >/dev/null
fi
cmake --build "$bin" -j "$(nproc)" --target strata-synth strata-convert strata-bench >/dev/null
synth=$bin/src/strata-synth convert=$bin/preprocess/strata-convert bench=$bin/src/bench/strata-bench

# make NAME SCENE POINTS [synth options]: LAS + truth sidecar, converted to NAME.strata.
make_scene() {
    local name=$1 scene=$2 points=$3
    shift 3
    [ -f "$work/$name.strata" ] && return
    echo "scene $name ($scene, $points points)" >&2
    $synth "$scene" --points "$points" -o "$work/$name.las" --quiet "$@"
    $convert "$work/$name.las" -o "$work/$name.strata" --force >/dev/null
}
make_scene sphere sphere $analytic
make_scene planes planes $analytic
make_scene nested nested $analytic
scenes="sphere planes nested"
bunny=$repo/../shared/data/models/bun_zipper.ply
if [ -f "$bunny" ]; then
    make_scene bunny mesh $analytic --mesh "$bunny"
    scenes="$scenes bunny"
fi
make_scene street street $street_points
for n in $street_sizes; do make_scene "street-$n" street "$n"; done

run() { # run OUTDIR strata-bench arguments...
    local dir=$1
    shift
    echo "strata-bench $*" >&2
    $bench --quiet --size "$size" --repeat "$repeat" --out "$dir" "$@"
}
# 1. Methods: every HPR variant and normal estimator on every scene; Katz on a smaller view.
for s in $scenes; do
    run "$out/methods-$s" "$work/$s.strata" --orbit "$views" --pipelines shaded \
        --normals pyramid,ld,pd,pc,ti --samples 9,25 --hpr pyramid,exhaustive --no-image-error
done
run "$out/methods-street" "$work/street.strata" --street "$views" --pipelines shaded \
    --normals pyramid,ld,pd,pc,ti --samples 9,25 --hpr pyramid,exhaustive --no-image-error
$bench --quiet --size "$katz_size" --repeat 1 --out "$out/katz" "$work/sphere.strata" \
    "$work/nested.strata" --orbit "$views" --pipelines hpr --hpr pyramid,exhaustive --katz \
    --katz-live --no-image-error
# 2. Frame time against scene size at a fixed budget.
args=()
for n in $street_sizes; do args+=("$work/street-$n.strata"); done
run "$out/size" "${args[@]}" --street "$views" --budgets "$size_budget" --pipelines raw,shaded \
    --no-image-error
# 3. Error against budget.
run "$out/budget" "$work/street.strata" --street "$views" --budgets "$budgets" \
    --pipelines shaded --normals pyramid,pd

# Means over views of the named columns, grouped by the key columns (one line per group,
# the key joined by '|'); rows of every CSV given, header taken from the first.
aggregate() { # aggregate "key1 key2" "val1 val2" files...
    local keys=$1 vals=$2
    shift 2
    awk -F, -v keys="$keys" -v vals="$vals" '
        FNR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        {
            nk = split(keys, k, " "); nv = split(vals, v, " ")
            key = $col[k[1]]; for (i = 2; i <= nk; i++) key = key "|" $col[k[i]]
            if (!(key in n)) order[++groups] = key
            n[key]++
            for (i = 1; i <= nv; i++) { x = $col[v[i]]; if (x == "inf") x = 99; sum[key, i] += x }
        }
        END {
            for (g = 1; g <= groups; g++) {
                key = order[g]; line = key
                for (i = 1; i <= nv; i++) line = line " " sum[key, i] / n[key]
                print line
            }
        }' "$@"
}
cd "$out"
aggregate "setting" "normals_ms normal_mean_deg hpr_ms hpr_f1" methods-*/results.csv \
    > methods.dat
aggregate "hpr" "hpr_ms hpr_f1 katz_ms katz_f1" katz/results.csv > katz.dat
aggregate "pipeline scene_points" "frame_ms gpu_ms geometry_ms" size/results.csv \
    | tr '|' ' ' > size.dat
aggregate "setting budget" "normal_mean_deg hpr_f1 psnr_db ssim depth_rel_mean" \
    budget/results.csv | tr '|' ' ' > budget.dat

gnuplot <<GNUPLOT
set terminal pngcairo size 1400,600 font ",10" noenhanced
set datafile separator " "
set output "time_vs_error.png"
set multiplot layout 1,2 title "Method cost against error (mean over scenes and views, $size)"
set xlabel "normal pass time (ms)"
set ylabel "normal angle error, mean (degrees)"
set grid
plot "methods.dat" using 2:3:1 with labels point pt 7 offset 0.5,0.5 left notitle
set xlabel "HPR pass time (ms)"
set ylabel "HPR F1 against true visibility"
plot "methods.dat" using 4:5 with points pt 7 title "screen-space HPR (per setting)", \
     "katz.dat" using 4:5:(sprintf("Katz (Qhull), %s-size view", "$katz_size")) every ::0::0 \
         with labels point pt 5 offset 0.5,-0.5 left notitle, \
     "katz.dat" using 2:3:1 with labels point pt 9 offset 0.5,0.5 left notitle
# katz.dat's "katz-live" line: the live mode's hull time (worker thread) and the F1 of its
# subsample, beside pyramid and exhaustive (docs/KATZ.md, Live mode).
unset multiplot

set terminal pngcairo size 900,600 font ",10" noenhanced
set output "frame_vs_size.png"
set title "Frame time against scene size (street, budget $size_budget, $size)"
set xlabel "points in the scene"
set ylabel "time (ms)"
set logscale x
plot "size.dat" using (strcol(1) eq "raw" ? \$2 : 1/0):3 with linespoints pt 7 title "raw: frame", \
     "size.dat" using (strcol(1) eq "shaded" ? \$2 : 1/0):3 with linespoints pt 7 title "shaded: frame", \
     "size.dat" using (strcol(1) eq "shaded" ? \$2 : 1/0):5 with linespoints pt 5 title "geometry pass"
unset logscale x

set terminal pngcairo size 1400,600 font ",10" noenhanced
set output "error_vs_budget.png"
set multiplot layout 1,2 title "Error against point budget ($size; PSNR 99 = identical to the unbudgeted render)"
unset title
set logscale x
set xlabel "budget (points per frame)"
set ylabel "normal angle error, mean (degrees)"
plot for [s in "shaded/pyramid/hpr-pyr shaded/pd9/hpr-pyr"] "budget.dat" \
     using (strcol(1) eq s ? \$2 : 1/0):3 with linespoints pt 7 title s
set ylabel "PSNR against the unbudgeted render (dB)"
plot for [s in "shaded/pyramid/hpr-pyr shaded/pd9/hpr-pyr"] "budget.dat" \
     using (strcol(1) eq s ? \$2 : 1/0):5 with linespoints pt 7 title s
unset multiplot
GNUPLOT
echo "report: $out/{time_vs_error,frame_vs_size,error_vs_budget}.png and */results.csv" >&2
