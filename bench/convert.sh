#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Converter speed and memory on a synthetic street scan (issue 3's reference case):
# makes a POINTS-point LAS 1.2 format-3 street scene, converts it with compression on,
# and prints points/s, peak RSS and the time per phase. Repeats RUNS times (the machine
# is shared: take the best, report the spread).
# usage: bench/convert.sh [POINTS=20000000] [RUNS=3] [extra strata-convert options...]
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-20000000}
runs=${2:-3}
shift $(( $# > 2 ? 2 : $# )) || true
bin=build/release
[ -x $bin/preprocess/strata-convert ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
las="$work/street-$points.las"
[ -f "$las" ] || $bin/src/strata-synth street --points "$points" --format 3 --seed 1 -o "$las" --quiet
echo "input: $las ($(du -h "$las" | cut -f1)), $(nproc) cores"
for run in $(seq 1 "$runs"); do
    /usr/bin/time -f "  wall %e s, user %U s, sys %S s, peak RSS %M KB" \
        $bin/preprocess/strata-convert "$las" -o "$work/street.strata" --force "$@" 2>&1 | sed 's/^/  /'
done
rm -f "$work/street.strata"
