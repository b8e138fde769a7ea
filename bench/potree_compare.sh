#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-convert against PotreeConverter 2 (not packaged here: give the path of a
# binary built from its source) and, optionally, another strata-convert build (e.g.
# main's), on one `strata-synth street` input. Runs are interleaved (A B C A B C ...)
# so that load from other users of the machine hits every program alike; prints each
# run, then medians and the ratios of the medians, of the wall time and of the CPU
# time (user + system: steadier than the wall time when other work shares the cores).
# usage: bench/potree_compare.sh [POINTS=20000000] [RUNS=3] [POTREE_BINARY] [BASE_CONVERT]
#   POTREE_BINARY  PotreeConverter; its default (Poisson) and `-m random` are timed
#   BASE_CONVERT   a second strata-convert binary to compare with this build's
# environment: BENCH_DIR (default /tmp/strata-bench) holds the input and outputs.
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
runs=${2:-3}
potree=${3:-}
base=${4:-}
bin=build/release
[ -x $bin/preprocess/strata-convert ] || { cmake --preset release >/dev/null && cmake --build --preset release -j2 >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
las="$work/street-$points.las"
[ -f "$las" ] || $bin/src/strata-synth street --points "$points" --format 3 --seed 1 -o "$las" --quiet
echo "input: $las ($(du -h "$las" | cut -f1)), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"

declare -A names cmds
order=()
add() { order+=("$1"); names[$1]=$2; cmds[$1]=$3; }
add strata "strata-convert (this build)" "$bin/preprocess/strata-convert $las -o $work/out.strata --force -q"
[ -n "$base" ] && add base "strata-convert ($base)" "$base $las -o $work/base.strata --force -q"
if [ -n "$potree" ]; then
    add poisson "PotreeConverter (default, Poisson)" "$potree $las -o $work/potree-poisson"
    add random "PotreeConverter -m random" "$potree $las -o $work/potree-random -m random"
fi

declare -A times cpus
for run in $(seq 1 "$runs"); do
    for key in "${order[@]}"; do
        rm -rf "$work/potree-poisson" "$work/potree-random"
        /usr/bin/time -o "$work/time.txt" -f "%e %M %U %S" ${cmds[$key]} >/dev/null 2>&1
        read -r wall rss user sys < <(tail -1 "$work/time.txt")
        cpu=$(echo "$user + $sys" | bc -l)
        times[$key]="${times[$key]:-} $wall"
        cpus[$key]="${cpus[$key]:-} $cpu"
        echo "  run $run: ${names[$key]}: $wall s, CPU $cpu s, peak RSS $(( rss / 1024 )) MiB"
    done
done
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
echo "medians of $runs (load now $(cut -d' ' -f1-3 /proc/loadavg)):"
ref=$(echo "${times[strata]}" | median)
cref=$(echo "${cpus[strata]}" | median)
for key in "${order[@]}"; do
    m=$(echo "${times[$key]}" | median)
    c=$(echo "${cpus[$key]}" | median)
    printf "  %-40s %8.2f s  %5.2fx strata's time  (runs:%s)\n" "${names[$key]}" "$m" \
        "$(echo "$m / $ref" | bc -l)" "${times[$key]}"
    printf "  %-40s %8.2f s  %5.2fx strata's CPU   (runs:%s)\n" "  CPU (user + system)" "$c" \
        "$(echo "$c / $cref" | bc -l)" "${cpus[$key]}"
done
du -sh "$work/out.strata" | sed 's/^/  output: /'
[ -n "$potree" ] && du -sh "$work/potree-random" 2>/dev/null | sed 's/^/  potree output: /'
rm -rf "$work/out.strata" "$work/base.strata" "$work/potree-poisson" "$work/potree-random"
