#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# How far the compute rasteriser's picture is from GL_POINTS' (issue 20 part 4, the
# stated tolerance in docs/PIPELINE.md): the demo street (strata-synth street --points
# 2000000 --seed 1, the demo camera) rendered --pipeline raw at SIZE with each
# rasteriser; prints the covered pixels (not the background colour in the GL_POINTS
# render), the differing pixels (ImageMagick compare -metric AE) and the agreement.
# usage: bench/raster_agreement.sh [BUILD=build/release]
#   (SIZE: default 1920x1080; BENCH_DIR: work folder, default /tmp/strata-agreement)
set -euo pipefail
build=${1:-build/release}
size=${SIZE:-1920x1080}
work=${BENCH_DIR:-/tmp/strata-agreement}
mkdir -p "$work"
scene=$work/street.strata
if [ ! -f "$scene" ]; then
    "$build/src/strata-synth" street --points 2000000 --seed 1 -o "$work/street.las" --quiet
    "$build/preprocess/strata-convert" "$work/street.las" -o "$scene" --force -q
    rm -f "$work/street.las"
fi
camera=650235,5401873.6,105.5,180,-8,70
for raster in points compute; do
    "$build/src/strata-view" --headless "$scene" --camera=$camera --size "$size" \
        --pipeline raw --raster $raster --out "$work/raw_$raster.png" >/dev/null
done
background=$(convert "$work/raw_points.png" -format '%[pixel:p{0,0}]' info:)
covered=$(convert "$work/raw_points.png" -fill black -opaque "$background" \
    -fill white +opaque black -format '%[fx:round(mean*w*h)]' info:)
differ=$(compare -metric AE "$work/raw_points.png" "$work/raw_compute.png" null: 2>&1 || true)
python3 -c "import sys; c, d = int(sys.argv[1]), int(float(sys.argv[2]))
print('%s: %d covered pixels, %d differ, %.3f %% agree' % (sys.argv[3], c, d, 100 - 100 * d / c))" \
    "$covered" "$differ" "$size"
