#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Peak RSS of strata-convert --normals against --memory (issue 12, part 1): every input
# at each --memory and thread count, one run each, with /usr/bin/time -v. Prints one
# line a run: the peak RSS, whether it is within --memory, wall and CPU (user + sys),
# and from the converter's summary the normals' pool, the most a chunk took and how
# many chunks ran alone (or the error when one cannot fit even alone).
#
#   bench/normals_memory.sh CONVERT INPUT... (an input "a.laz+b.laz" is one run of both)
#
# MEMORY="2048 1024 768" (MiB; 2048 is the default), THREADS="1 2",
# BENCH_DIR=/tmp/strata-normals-memory.
set -uo pipefail
[ $# -ge 2 ] || {
    sed -n '3,12p' "$0"
    exit 2
}
convert=$1
shift
work=${BENCH_DIR:-/tmp/strata-normals-memory}
mkdir -p "$work"
echo "$(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg), $(date -u +%H:%M) UTC"
printf '%-28s %6s %3s %8s %6s %7s %7s %9s %9s %5s  %s\n' input memory thr "RSS MiB" within \
    "wall s" "CPU s" "pool MiB" "chunk MiB" alone status
for input in "$@"; do
    IFS=+ read -r -a files <<<"$input"
    for memory in ${MEMORY:-2048 1024 768}; do
        for threads in ${THREADS:-1 2}; do
            log="$work/run.log"
            /usr/bin/time -v "$convert" "${files[@]}" -o "$work/out.strata" --force --normals \
                --memory "$memory" --threads "$threads" >"$log" 2>&1
            rc=$?
            rss=$(awk -F': ' '/Maximum resident/ { print int($2 / 1024) }' "$log")
            user=$(awk -F': ' '/User time/ { print $2 }' "$log")
            sys=$(awk -F': ' '/System time/ { print $2 }' "$log")
            wall=$(awk '/Elapsed \(wall/ { n = split($NF, t, ":"); s = 0;
                for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s }' "$log")
            pool=$(sed -n 's/.*normals memory: \([0-9]*\) MiB.*/\1/p' "$log")
            chunk=$(sed -n 's/.*normals, \([0-9]*\) MiB the most.*/\1/p' "$log")
            alone=$(sed -n 's/.*took; \([0-9]*\) chunks ran alone.*/\1/p' "$log")
            status=ok
            [ "$rc" = 0 ] || status="error: $(grep -m1 'strata-convert:' "$log" | cut -c1-400)"
            within=yes
            [ "$rss" -le "$memory" ] || within=NO
            printf '%-28s %6s %3s %8s %6s %7.2f %7.2f %9s %9s %5s  %s\n' \
                "$(basename "${files[0]}")$([ ${#files[@]} -gt 1 ] && echo "+$((${#files[@]} - 1))")" \
                "$memory" "$threads" "$rss" "$within" "$wall" "$(echo "$user + $sys" | bc)" \
                "${pool:--}" "${chunk:--}" "${alone:--}" "$status"
        done
    done
done
rm -f "$work/out.strata" "$work/run.log"
