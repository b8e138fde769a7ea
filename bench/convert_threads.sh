#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# How each phase of strata-convert scales with threads: `--threads 1` and `--threads N`
# interleaved (1 N 1 N ...) on one `strata-synth street` input; prints each run's
# phase times, then per phase the medians and the speed-up (1 thread / N threads).
# usage: bench/convert_threads.sh [POINTS=20000000] [RUNS=3] [N=nproc] [CONVERT]
#   CONVERT  the strata-convert binary (default: this build's)
# environment: BENCH_DIR (default /tmp/strata-bench) holds the input and outputs.
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
runs=${2:-3}
threads=${3:-$(nproc)}
bin=${4:-build/release/preprocess/strata-convert}
[ -x "$bin" ] || { cmake --preset release >/dev/null && cmake --build --preset release -j2 >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
las="$work/street-$points.las"
[ -f "$las" ] || build/release/src/strata-synth street --points "$points" --format 3 --seed 1 \
    -o "$las" --quiet
echo "input: $las, $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
declare -A t
phases="count distribute index merge finish total"
for run in $(seq 1 "$runs"); do
    for n in 1 "$threads"; do
        line=$("$bin" "$las" -o "$work/threads.strata" --force --threads "$n" 2>&1 |
            grep -E 'phases:|points,')
        total=$(echo "$line" | grep -o '[0-9.]* s (' | grep -o '^[0-9.]*')
        echo "  run $run, --threads $n: total $total s; $(echo "$line" | grep -o 'count.*merge')"
        for p in $phases; do
            v=$([ "$p" = total ] && echo "$total" || echo "$line" | grep -o "$p [0-9.]* s" | grep -o '[0-9.]*')
            t[$p,$n]="${t[$p,$n]:-} $v"
        done
    done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "medians of $runs (load now $(cut -d' ' -f1-3 /proc/loadavg)):"
for p in $phases; do
    a=$(echo "${t[$p,1]}" | median)
    b=$(echo "${t[$p,$threads]}" | median)
    up=$(echo "$b > 0" | bc -l | grep -q 1 && echo "$a / $b" | bc -l || echo 0)
    printf "  %-10s 1 thread %6.2f s   %d threads %6.2f s   speed-up %4.2fx\n" "$p" "$a" \
        "$threads" "$b" "$up"
done
rm -f "$work/threads.strata"
