#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Renders the pictures of docs/PIPELINE.md and docs/VIEWER.md into docs/images/: the
# Stanford bunny and a strata-synth street scan after each stage of the screen-space
# pipeline (headless, Mesa llvmpipe is enough).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=build/release
[ -x $bin/src/strata-view ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
out=docs/images
mkdir -p "$work" "$out"
data=../shared/data
size=640x480

if [ -f $data/models/bun_zipper.ply ]; then
    $bin/preprocess/strata-convert $data/models/bun_zipper.ply -o "$work/bunny.strata" --force -q
    for mode in raw hpr fill normals shaded edl; do
        # The bunny is y-up (the converter writes up_axis +Y): yaw 90 pitch 0 looks along -Z.
        $bin/src/strata-view --headless "$work/bunny.strata" --camera=-0.017,0.11,0.3,90,0,40 \
            --size $size --pipeline $mode --colour intensity --out "$out/bunny_$mode.png"
    done
else
    echo "pictures: $data/models/bun_zipper.ply is absent: no bunny pictures" >&2
fi

$bin/src/strata-synth street --points 2000000 --seed 1 -o "$work/street2m.las" --quiet
$bin/preprocess/strata-convert "$work/street2m.las" -o "$work/street2m.strata" --force -q
# Standing on the road, 2.2 m up, looking down the street.
street_camera=650235,5401873.6,105.5,180,-8,70
for mode in raw hpr fill normals shaded edl; do
    $bin/src/strata-view --headless "$work/street2m.strata" --camera=$street_camera \
        --size $size --pipeline $mode --out "$out/street_$mode.png"
done
$bin/src/strata-view --headless "$work/street2m.strata" --size 960x540 --pipeline raw \
    --out "$out/street_overview.png"
$bin/src/strata-view --headless "$work/street2m.strata" --camera=$street_camera --size 960x540 \
    --pipeline raw --colour class --out "$out/street_classes.png"
ls -la "$out"
