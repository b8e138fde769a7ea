#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Scale run of the converter (issue 3): a POINTS-point strata-synth street scan (LAS 1.4
# format 7) converted with a memory budget, peak RSS and points/s recorded. Needs about
# 80 bytes of free disk per point (input, temporary file, output).
# usage: bench/scale.sh [POINTS=500000000] [MEMORY_MIB=2048]
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-500000000}
memory=${2:-2048}
bin=build/release
[ -x $bin/preprocess/strata-convert ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
las="$work/street-$points-f7.las"
echo "== synth $points points -> $las"
[ -f "$las" ] || /usr/bin/time -f "  synth: wall %e s, peak RSS %M KB" \
    $bin/src/strata-synth street --points "$points" --seed 7 -o "$las" --quiet
df -h "$work" | tail -1
echo "== convert --memory $memory"
/usr/bin/time -f "  convert: wall %e s, user %U s, sys %S s, peak RSS %M KB" \
    $bin/preprocess/strata-convert "$las" -o "$work/street-$points.strata" --force --memory "$memory"
$bin/src/strata-info "$work/street-$points.strata" | tail -20
