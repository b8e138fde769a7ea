#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The cost of adaptive neighbourhoods (issue 12): strata-convert --normals of one
# strata-synth street with this build at K = 10 (widening the nearly linear and edge-on
# neighbourhoods to 40) against a reference binary without widening (the merge base,
# copied beforehand) at K = 10 and at K = 40. Rounds interleaved (ref 10, new 10,
# ref 40), medians of wall and CPU (user + sys) seconds, and their ratios per round.
#
#   bench/normals_adaptive.sh REF_CONVERT [POINTS=4000000] [RUNS=3]
set -euo pipefail
cd "$(dirname "$0")/.."
ref=$1
points=${2:-4000000}
runs=${3:-3}
bin=build/release
work=${BENCH_DIR:-/tmp/strata-normals-bench}
mkdir -p "$work"
las="$work/street-$points.las"
[ -f "$las" ] || $bin/src/strata-synth street --points "$points" --format 3 --seed 1 -o "$las" --quiet
echo "input: $las ($points points), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
: >"$work/adaptive.txt"
for run in $(seq 1 "$runs"); do
    for v in ref10 new10 ref40; do
        case $v in
        ref10) cmd=("$ref" --knn 10) ;;
        new10) cmd=($bin/preprocess/strata-convert --knn 10) ;;
        ref40) cmd=("$ref" --knn 40) ;;
        esac
        /usr/bin/time -f "$v %e %U %S" -o "$work/time.txt" \
            "${cmd[@]}" "$las" -o "$work/adaptive.strata" --force --normals -q
        awk '{ printf "%s %.2f %.2f\n", $1, $2, $3 + $4 }' "$work/time.txt" | tee -a "$work/adaptive.txt"
    done
    echo "  load $(cut -d' ' -f1 /proc/loadavg)"
done
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "| run | median wall s | median CPU s |"
echo "|---|---|---|"
for v in ref10 new10 ref40; do
    echo "| $v | $(awk -v t=$v '$1 == t { print $2 }' "$work/adaptive.txt" | median) | $(awk -v t=$v '$1 == t { print $3 }' "$work/adaptive.txt" | median) |"
done
echo "CPU ratios per round, new10 / ref10 and ref40 / ref10:"
awk '{ c[$1] = $3 } $1 == "ref40" { printf "  %.2f %.2f\n", c["new10"] / c["ref10"], c["ref40"] / c["ref10"] }' "$work/adaptive.txt"
