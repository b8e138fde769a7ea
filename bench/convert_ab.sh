#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Several strata-convert binaries (e.g. a merge base copied to /tmp and this build)
# on one input, interleaved (A B C A B C ...) so that load from other users of the
# machine hits each alike; prints each run's wall and CPU time (user + system) and
# the load average, then the medians. Used to measure one change at a time.
# usage: bench/convert_ab.sh RUNS INPUT BINARY... [-- CONVERT_OPTIONS...]
# example: bench/convert_ab.sh 5 /tmp/strata-bench/street-20000000.las /tmp/base \
#          build/release/preprocess/strata-convert
# environment: BENCH_DIR (default /tmp/strata-bench) holds the outputs.
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '3,10p' "$0" | cut -c3-; exit 0 ;; esac
[ $# -ge 3 ] || { sed -n '3,10p' "$0" | cut -c3- >&2; exit 2; }
runs=$1
input=$2
shift 2
bins=()
while [ $# -gt 0 ] && [ "$1" != -- ]; do
    bins+=("$1")
    shift
done
[ $# -gt 0 ] && shift # the options after --
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
declare -A walls cpus
for run in $(seq 1 "$runs"); do
    for i in "${!bins[@]}"; do
        /usr/bin/time -o "$work/ab-time.txt" -f "%e %U %S" "${bins[$i]}" "$input" \
            -o "$work/ab-$i.strata" --force -q "$@" >/dev/null 2>&1
        read -r wall user sys <"$work/ab-time.txt"
        cpu=$(echo "$user + $sys" | bc -l)
        walls[$i]="${walls[$i]:-} $wall"
        cpus[$i]="${cpus[$i]:-} $cpu"
        echo "  run $run ${bins[$i]}: wall $wall s, CPU $cpu s (user $user, sys $sys), load $(cut -d' ' -f1 /proc/loadavg)"
    done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "medians of $runs (load now $(cut -d' ' -f1-3 /proc/loadavg)):"
for i in "${!bins[@]}"; do
    echo "  ${bins[$i]}: wall $(echo "${walls[$i]}" | median) s, CPU $(echo "${cpus[$i]}" | median) s"
done
for i in "${!bins[@]}"; do
    cmp -s "$work/ab-0.strata" "$work/ab-$i.strata" || echo "  ${bins[$i]}: output differs from ${bins[0]}'s"
done
rm -f "$work"/ab-*.strata "$work/ab-time.txt"
