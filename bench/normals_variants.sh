#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The CPU of whole strata-convert --normals conversions of one LAS by several binaries
# (variants of a change, each a copy made beforehand), interleaved A B C A B C ..., with
# wall and CPU (user + sys) seconds per run, their medians, and each variant's CPU over
# the first one's per round and its median (the machine is shared: only ratios within a
# round are compared).
#
#   bench/normals_variants.sh LAS RUNS NAME=BINARY [NAME=BINARY ...]
#
# THREADS=N: every run with --threads N (default 1: a single thread's CPU time is the
# least disturbed by other work). Work files go to $BENCH_DIR (default
# /tmp/strata-normals-variants).
set -euo pipefail
if [ $# -lt 3 ] || [ "$1" = --help ]; then
    sed -n '3,13p' "$0" | sed 's/^# \{0,1\}//'
    [ "${1:-}" = --help ] && exit 0 || exit 2
fi
las=$1
runs=$2
shift 2
[ -f "$las" ] || { echo "normals_variants: $las: no such file" >&2; exit 2; }
work=${BENCH_DIR:-/tmp/strata-normals-variants}
mkdir -p "$work"
names=()
bins=()
for v in "$@"; do
    names+=("${v%%=*}")
    bins+=("${v#*=}")
    [ -x "${v#*=}" ] || { echo "normals_variants: ${v#*=}: not an executable" >&2; exit 2; }
done
echo "input: $las, $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
: >"$work/variants.txt"
for run in $(seq 1 "$runs"); do
    for i in "${!names[@]}"; do
        /usr/bin/time -f "${names[$i]} $run %e %U %S" -o "$work/time.txt" "${bins[$i]}" "$las" \
            -o "$work/out.strata" --normals --force -q --threads "${THREADS:-1}"
        awk '{ printf "%s %s %.2f %.2f\n", $1, $2, $3, $4 + $5 }' "$work/time.txt" | tee -a "$work/variants.txt"
    done
    echo "  load $(cut -d' ' -f1 /proc/loadavg)"
done
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
echo "| variant | median wall s | median CPU s | CPU / ${names[0]}'s per round | median ratio |"
echo "|---|---|---|---|---|"
for name in "${names[@]}"; do
    ratios=$(awk -v a="${names[0]}" -v b="$name" '$1 == a { r[$2] = $4 } $1 == b { c[$2] = $4 }
        END { for (k in c) if (r[k] > 0) printf "%d %.3f\n", k, c[k] / r[k] }' "$work/variants.txt" | sort -n | awk '{ print $2 }')
    echo "| $name | $(awk -v t="$name" '$1 == t { print $3 }' "$work/variants.txt" | median) |" \
        "$(awk -v t="$name" '$1 == t { print $4 }' "$work/variants.txt" | median) |" \
        "$(echo $ratios) | $(echo "$ratios" | median) |"
done
