#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The cost of strata-convert --normals against a plain conversion (issue 12), and
# against a reference binary (an earlier build copied beforehand, e.g. the merge base),
# on one strata-synth street. Rounds interleaved (plain, ref --normals, new --normals),
# wall and CPU (user + sys) seconds, medians, and the ratios per round: the machine is
# shared, so only ratios within a round are compared. Each run's index phase (wall, CPU
# of all threads and their ratio, from strata-convert's summary) goes to phases.txt.
#
#   bench/normals_speed.sh [REF_CONVERT|-] [POINTS=20000000] [RUNS=3] [K=10]
#
# NEW_CONVERT=path: the binary timed as plain and new (default build/release's; a copy
# keeps rebuilds during the run out of it). THREADS=N: every run with --threads N (a
# single thread's CPU time is the least disturbed by a shared machine). FINE=1: one more
# variant per round, "fine" (NEW with --normals-method moments-fine).
set -euo pipefail
cd "$(dirname "$0")/.."
ref=${1:--}
points=${2:-20000000}
runs=${3:-3}
k=${4:-10}
bin=build/release
new=${NEW_CONVERT:-$bin/preprocess/strata-convert}
work=${BENCH_DIR:-/tmp/strata-normals-bench}
mkdir -p "$work"
las="$work/street-$points.las"
[ -f "$las" ] || $bin/src/strata-synth street --points "$points" --seed 1 -o "$las" --quiet
echo "input: $las ($points points), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
variants="plain new"
[ "$ref" = - ] || variants="plain ref new"
[ -z "${FINE:-}" ] || variants="$variants fine"
: >"$work/speed.txt"
: >"$work/phases.txt"
for run in $(seq 1 "$runs"); do
    for v in $variants; do
        case $v in
        plain) cmd=("$new") ;;
        ref) cmd=("$ref" --normals --knn "$k") ;;
        new) cmd=("$new" --normals --knn "$k") ;;
        fine) cmd=("$new" --normals --knn "$k" --normals-method moments-fine) ;;
        esac
        [ -z "${THREADS:-}" ] || cmd+=(--threads "$THREADS")
        # Not -q: the summary's per-phase wall and CPU (all threads) lines are kept.
        /usr/bin/time -f "$v %e %U %S" -o "$work/time.txt" \
            "${cmd[@]}" "$las" -o "$work/speed-$v.strata" --force >"$work/report.txt" 2>&1
        awk '{ printf "%s %.2f %.2f\n", $1, $2, $3 + $4 }' "$work/time.txt" | tee -a "$work/speed.txt"
        # index phase: wall, CPU, their ratio (the parallelism of the index workers)
        awk -v t="$v" '/^  phases:/ { for (i = 1; i <= NF; i++) if ($i == "index") w = $(i + 1) }
                     /^  CPU \(all threads\):/ { for (i = 1; i <= NF; i++) if ($i == "index") c = $(i + 1) }
                     /halo pass/ { for (i = 1; i <= NF; i++) if ($i == "pass") h = $(i + 1) }
                     END { printf "%s %.2f %.2f %.2f %s\n", t, w, c, c / w, h == "" ? "-" : h }' \
            "$work/report.txt" | tee -a "$work/phases.txt" | awk '{ printf "    index %s s wall, %s s CPU (%s cores), halo pass %s s\n", $2, $3, $4, $5 }'
    done
    echo "  load $(cut -d' ' -f1 /proc/loadavg)"
done
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "| run | median wall s | median CPU s | all wall s |"
echo "|---|---|---|---|"
for v in $variants; do
    echo "| $v | $(awk -v t="$v" '$1 == t { print $2 }' "$work/speed.txt" | median) |" \
        "$(awk -v t="$v" '$1 == t { print $3 }' "$work/speed.txt" | median) |" \
        "$(awk -v t="$v" '$1 == t { printf "%s ", $2 }' "$work/speed.txt")|"
done
echo "| run | median index wall s | median index CPU s | median index CPU / wall |"
echo "|---|---|---|---|"
for v in $variants; do
    echo "| $v | $(awk -v t="$v" '$1 == t { print $2 }' "$work/phases.txt" | median) |" \
        "$(awk -v t="$v" '$1 == t { print $3 }' "$work/phases.txt" | median) |" \
        "$(awk -v t="$v" '$1 == t { print $4 }' "$work/phases.txt" | median) |"
done
echo "per round: new/plain wall, new/plain CPU, (with a reference) new/ref wall, new/ref CPU,"
echo "(with FINE) fine/plain wall, fine/plain CPU:"
awk -v last="${variants##* }" '{ w[$1] = $2; c[$1] = $3 }
     $1 == last { printf "  %.2f %.2f", w["new"] / w["plain"], c["new"] / c["plain"]
                  if ("ref" in w) printf "   %.2f %.2f", w["new"] / w["ref"], c["new"] / c["ref"]
                  if ("fine" in w) printf "   %.2f %.2f", w["fine"] / w["plain"], c["fine"] / c["plain"]
                  printf "\n" }' "$work/speed.txt"
