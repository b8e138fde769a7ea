#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# How each phase of strata-convert scales with threads: `--threads 1` and `--threads N`
# interleaved (1 N 1 N ...) on one `strata-synth street` input; prints each run's
# phase times (wall and CPU of all threads, from strata-convert's summary), then per
# phase the medians, the parallelism of the N-thread runs (CPU / wall: how many cores
# the phase kept busy, which a loaded machine lowers) and the speed-up (1 / N threads).
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
declare -A t c
phases="count distribute index merge finish total"
for run in $(seq 1 "$runs"); do
    for n in 1 "$threads"; do
        out=$("$bin" "$las" -o "$work/threads.strata" --force --threads "$n" 2>&1)
        line=$(echo "$out" | grep -E 'phases:|points,')
        cpu=$(echo "$out" | grep -E '^  CPU')
        total=$(echo "$line" | grep -o '[0-9.]* s (' | grep -o '^[0-9.]*')
        echo "  run $run, --threads $n: total $total s; $(echo "$line" | grep -o 'count.*merge')"
        echo "      CPU:$(echo "$cpu" | grep -o ' count.*finish [0-9.]* s')"
        ctotal=0
        for p in $phases; do
            v=$([ "$p" = total ] && echo "$total" || echo "$line" | grep -o "$p [0-9.]* s" | grep -o '[0-9.]*')
            t[$p,$n]="${t[$p,$n]:-} $v"
            if [ "$p" != total ]; then
                w=$(echo "$cpu" | grep -o "$p [0-9.]* s" | grep -o '[0-9.]*')
                ctotal=$(echo "$ctotal + $w" | bc -l)
            else
                w=$ctotal
            fi
            c[$p,$n]="${c[$p,$n]:-} $w"
        done
    done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
ratio() { echo "$2 > 0" | bc -l | grep -q 1 && echo "$1 / $2" | bc -l || echo 0; }
echo "medians of $runs (load now $(cut -d' ' -f1-3 /proc/loadavg)); wall, CPU of all threads,"
echo "and parallelism = CPU / wall (cores kept busy):"
for p in $phases; do
    a=$(echo "${t[$p,1]}" | median)
    b=$(echo "${t[$p,$threads]}" | median)
    ca=$(echo "${c[$p,1]}" | median)
    cb=$(echo "${c[$p,$threads]}" | median)
    printf "  %-10s 1 thread %6.2f s (CPU %5.2f s)   %d threads %6.2f s (CPU %5.2f s, parallelism %4.2f)   speed-up %4.2fx\n" \
        "$p" "$a" "$ca" "$threads" "$b" "$cb" "$(ratio "$cb" "$b")" "$(ratio "$a" "$b")"
done
rm -f "$work/threads.strata"
