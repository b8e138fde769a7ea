#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Viewer benchmarks (issue 4): frame time at a fixed budget on a small and a large scene
# from the same view, the loader's throughput against zstd alone, and the time from a
# camera jump to a fully refined view. Headless (EGL); on Mesa llvmpipe without a GPU.
# usage: bench/viewer.sh LARGE.strata [SMALL_POINTS=1000000] [SEED=7]
# LARGE.strata should be a strata-synth street scene made with the same seed (the
# street starts the same way whatever its length, so the view below shows the same).
set -euo pipefail
cd "$(dirname "$0")/.."
large=$1
small_points=${2:-1000000}
seed=${3:-7}
bin=build/release
[ -x $bin/src/strata-view ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
small="$work/street-$small_points-seed$seed.strata"
if [ ! -f "$small" ]; then
    $bin/src/strata-synth street --points "$small_points" --seed "$seed" -o "$work/small.las" --quiet
    $bin/preprocess/strata-convert "$work/small.las" -o "$small" --force -q
fi
camera=${CAMERA:-650245,5401873.6,105.5,0,-8,70}   # on the road near the start (seed 7 runs +x)
size=${SIZE:-1920x1080}
budget=${BUDGET:-1000000}
for scene in "$small" "$large"; do
    echo "== $(basename "$scene"): $($bin/src/strata-info "$scene" | grep '^points')"
    for pipeline in raw shaded; do
        echo "  pipeline $pipeline, budget $budget, $size:"
        $bin/src/strata-view --headless "$scene" --camera=$camera --size $size --budget $budget \
            --pipeline $pipeline --repeat 5 --stats | grep -E "view loaded|median" | sed 's/^/    /'
    done
    echo "  loader work per node, one thread:"
    $bin/src/strata-info --decode-speed "$scene" | tail -2 | sed 's/^/  /'
done
echo "== camera jump on $(basename "$large"): overview, then 1/30 s later the street view"
# A two-keyframe path: each path frame renders until fully loaded, so the second
# frame's load time is the time from the jump to a fully refined view.
cat > "$work/jump.json" <<JSON
{ "version": 1, "keyframes": [
  { "time": 0, "position": [650100, 5401700, 400], "yaw": 45, "pitch": -35, "fov": 70 },
  { "time": 0.03333334, "position": [650245, 5401873.6, 105.5], "yaw": 0, "pitch": -8, "fov": 70 } ] }
JSON
$bin/src/strata-view --headless "$large" --path "$work/jump.json" --size $size --budget $budget \
    --pipeline raw --stats | grep "view loaded" | sed 's/^/  /'
