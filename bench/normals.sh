#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-convert --normals (issue 12): speed against CloudCompare and PCL on one
# strata-synth street, and accuracy against the synth's truth.
#
#   bench/normals.sh [POINTS=20000000] [RUNS=2] [K=10]
#
# Speed, interleaved rounds (plain conversion, --normals conversion, CloudCompare
# -OCTREE_NORMALS auto, pcl_normal_estimation -k K), RUNS rounds, medians: every tool
# reads the same street (LAS for strata-convert; local x y z text for CloudCompare; an
# ASCII PCD for PCL, made once, not timed). CloudCompare's and PCL's own timings of the
# normals step are printed beside their whole runs.
# Accuracy (tests/tools/normals_accuracy): the street per class for all three, and the
# analytic scenes (sphere, planes, nested, 1 M points each) for strata-convert.
# The peers are installed here when missing (apt-get, as root); they are never a build
# or CI dependency. Work files go to $BENCH_DIR (default /tmp/strata-normals-bench).
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
runs=${2:-2}
k=${3:-10}
bin=build/release
[ -x $bin/tests/normals_accuracy ] || { cmake --preset release >/dev/null && cmake --build --preset release -j2 >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-normals-bench}
mkdir -p "$work"
if ! command -v CloudCompare >/dev/null || ! command -v pcl_normal_estimation >/dev/null ||
    ! command -v xvfb-run >/dev/null; then
    echo "installing the peers (cloudcompare, pcl-tools, xvfb)"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq cloudcompare pcl-tools xvfb xauth >/dev/null
fi

las="$work/street-$points.las"
[ -f "$las" ] || $bin/src/strata-synth street --points "$points" --seed 1 -o "$las" --quiet
# Local coordinates (the synth's utm origin subtracted): PCL stores float32.
if [ ! -f "$work/street-$points.pcd" ]; then
    $bin/src/strata-info "$las" --points "0:$points" |
        awk -F, 'NR > 1 { printf "%.3f %.3f %.3f\n", $1 - 650241.375, $2 - 5401873.625, $3 - 103.25 }' \
            >"$work/street-$points.xyz"
    { printf '# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n'
      printf 'WIDTH %s\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %s\nDATA ascii\n' "$points" "$points"
      cat "$work/street-$points.xyz"; } >"$work/street-$points.pcd"
fi
echo "input: $las ($points points), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"

wall() { # wall seconds of a command, its output kept in $work/last.log
    local t0 t1
    t0=$(date +%s.%N)
    "$@" >"$work/last.log" 2>&1
    t1=$(date +%s.%N)
    echo "$t1 - $t0" | bc
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

: >"$work/times.txt"
for run in $(seq 1 "$runs"); do
    t=$(wall $bin/preprocess/strata-convert "$las" -o "$work/plain.strata" --force)
    echo "plain $t" | tee -a "$work/times.txt"
    t=$(wall $bin/preprocess/strata-convert "$las" -o "$work/normals.strata" --force --normals --knn "$k")
    echo "normals $t" | tee -a "$work/times.txt"
    grep "phases\|normals:" "$work/last.log" | sed 's/^/    /'
    t=$(wall xvfb-run -a CloudCompare -SILENT -AUTO_SAVE OFF -O "$work/street-$points.xyz" \
        -OCTREE_NORMALS auto -C_EXPORT_FMT ASC -PREC 6 -SAVE_CLOUDS FILE "$work/cc.asc")
    own=$(grep -o 'Timing: [0-9.]* s' "$work/last.log" | awk '{print $2}')
    echo "cloudcompare $t" | tee -a "$work/times.txt"
    echo "cloudcompare_normals $own" | tee -a "$work/times.txt"
    grep -h "Cloud radius" "$work/last.log" | sed 's/^/    /' || true
    t=$(wall pcl_normal_estimation "$work/street-$points.pcd" "$work/pcl.pcd" -k "$k")
    own=$(grep -o 'normals in [0-9.]* ms' "$work/last.log" | awk '{print $3 / 1000}')
    echo "pcl $t" | tee -a "$work/times.txt"
    echo "pcl_normals $own" | tee -a "$work/times.txt"
done
echo
echo "| tool | median wall s | runs |"
echo "|---|---|---|"
for tool in plain normals cloudcompare cloudcompare_normals pcl pcl_normals; do
    m=$(awk -v t=$tool '$1 == t { print $2 }' "$work/times.txt" | median)
    all=$(awk -v t=$tool '$1 == t { printf "%s ", $2 }' "$work/times.txt")
    echo "| $tool | $m | $all|"
done

echo
echo "accuracy, street ($points points), K = $k:"
echo "strata-convert --normals:"
$bin/tests/normals_accuracy "$work/normals.strata" street "$points" 1 utm
pcl_convert_pcd_ascii_binary "$work/pcl.pcd" "$work/pcl_ascii.pcd" 0 >/dev/null
awk 'f { print $1, $2, $3 } /^DATA/ { f = 1 }' "$work/pcl_ascii.pcd" >"$work/pcl.txt"
awk '{ print $4, $5, $6 }' "$work/cc.asc" >"$work/cc.txt"
echo "PCL (-k $k):"
$bin/tests/normals_accuracy --peer "$work/pcl.txt" "$las" street "$points" 1 utm
echo "CloudCompare (-OCTREE_NORMALS auto):"
$bin/tests/normals_accuracy --peer "$work/cc.txt" "$las" street "$points" 1 utm
rm -f "$work/pcl_ascii.pcd" "$work/pcl.txt" "$work/cc.txt"

echo
echo "accuracy, analytic scenes (1 M points, generator noise 0), K = $k:"
for scene in sphere planes nested; do
    $bin/src/strata-synth $scene --points 1M --seed 1 -o "$work/$scene.las" --quiet
    $bin/preprocess/strata-convert "$work/$scene.las" -o "$work/$scene.strata" --force --normals --knn "$k" -q
    $bin/tests/normals_accuracy "$work/$scene.strata" $scene 1000000 1 utm | tail -n +3
done
