#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Scale run of the converter (issues 3, 17): a POINTS-point strata-synth street scan (LAS
# 1.4 format 7, or 1.2 format 3) converted with a memory budget, peak RSS, points/s and
# the temporary peak recorded, then verified. Needs about 52 bytes of free disk per
# point for format 3 (input 34, temporary runs ~9, output ~9).
# usage: bench/scale.sh [POINTS=500000000] [MEMORY_MIB=2048] [FORMAT=7] [SEED=7]
set -euo pipefail
cd "$(dirname "$0")/.."
points=${1:-500000000}
memory=${2:-2048}
format=${3:-7}
seed=${4:-7}
bin=build/release
[ -x $bin/preprocess/strata-convert ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
las="$work/street-$points-f$format.las"
echo "== synth $points points -> $las"
[ -f "$las" ] || /usr/bin/time -f "  synth: wall %e s, peak RSS %M KB" \
    $bin/src/strata-synth street --points "$points" --format "$format" --seed "$seed" -o "$las" --quiet
df -h "$work" | tail -1
echo "== convert --memory $memory"
/usr/bin/time -f "  convert: wall %e s, user %U s, sys %S s, peak RSS %M KB" \
    $bin/preprocess/strata-convert "$las" -o "$work/street-$points.strata" --force --memory "$memory"
$bin/src/strata-info "$work/street-$points.strata" | tail -20
echo "== verify"
/usr/bin/time -f "  verify: wall %e s" $bin/src/strata-info --verify "$work/street-$points.strata" | tail -1
ls -l "$las" "$work/street-$points.strata"
