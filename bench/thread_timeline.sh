#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Where each thread of a command spends its time (issue 12: is the index phase of
# strata-convert --normals parallel, or does a worker wait?). Samples
# /proc/PID/task/*/schedstat every INTERVAL seconds: per thread and interval, the time
# it ran, the time it was runnable but waited for a core (other processes on a shared
# machine), and the rest (blocked: a lock, a condition variable, I/O, or not yet
# started / already ended). Then the sums per thread over the whole run.
#
#   bench/thread_timeline.sh [INTERVAL=2] -- COMMAND...
set -euo pipefail
interval=2
if [ "${1:-}" != -- ]; then
    interval=$1
    shift
fi
[ "${1:-}" = -- ] && shift
[ $# -gt 0 ] || { echo "usage: $0 [INTERVAL] -- COMMAND..." >&2; exit 2; }
log=$(mktemp)
trap 'rm -f "$log"' EXIT
"$@" &
pid=$!
start=$(date +%s.%N)
while kill -0 "$pid" 2>/dev/null; do
    now=$(date +%s.%N)
    for task in /proc/"$pid"/task/*; do
        # comm, ran ns, waited ns (a thread may end between the two reads)
        read -r comm <"$task/comm" 2>/dev/null || continue
        read -r ran waited _ <"$task/schedstat" 2>/dev/null || continue
        echo "$now ${task##*/} $comm $ran $waited" >>"$log"
    done
    sleep "$interval"
done
wait "$pid"
status=$?
awk -v start="$start" '
    { t = $1 - start; key = $2 " " $3
      if (key in last_t) {
          dt = t - last_t[key]; r = ($4 - last_r[key]) / 1e9; w = ($5 - last_w[key]) / 1e9
          printf "%7.1f s  %-16s ran %5.1f %%  waited for a core %5.1f %%  blocked %5.1f %%\n",
                 t, $3, 100 * r / dt, 100 * w / dt, 100 * (dt - r - w) / dt
          sum_dt[key] += dt; sum_r[key] += r; sum_w[key] += w
      }
      last_t[key] = t; last_r[key] = $4; last_w[key] = $5 }
    END { print "per thread over its sampled life:"
          for (k in sum_dt) {
              split(k, f, " ")
              printf "  %-16s %6.1f s sampled: ran %5.1f %%, waited for a core %5.1f %%, blocked %5.1f %%\n",
                     f[2], sum_dt[k], 100 * sum_r[k] / sum_dt[k], 100 * sum_w[k] / sum_dt[k],
                     100 * (sum_dt[k] - sum_r[k] - sum_w[k]) / sum_dt[k]
          } }' "$log"
exit $status
