#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Issue 12's pictures in docs/VIEWER.md: the Stanford bunny and the strata-synth street
# of bench/pictures.sh, converted with --normals and drawn as splats: the bunny with
# bunny_shaded.png's camera and size; the street (its camera) and a narrow view of the
# parked cars, each as splats and as the shaded pipeline, small (PNGs under 200 KB).
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
    $bin/preprocess/strata-convert $data/models/bun_zipper.ply -o "$work/bunny_normals.strata" \
        --normals --force -q
    $bin/src/strata-view --headless "$work/bunny_normals.strata" --camera=-0.017,0.11,0.3,90,0,40 \
        --size $size --pipeline splats --colour intensity --out "$out/splats_bunny.png"
else
    echo "splat pictures: $data/models/bun_zipper.ply is absent: no bunny picture" >&2
fi

$bin/src/strata-synth street --points 2000000 --seed 1 -o "$work/street2m.las" --quiet
$bin/preprocess/strata-convert "$work/street2m.las" -o "$work/street2m_normals.strata" --normals \
    --force -q
# The street from the road (bench/pictures.sh's camera), and the parked cars across it
# through a narrow field of view.
street_camera=650235,5401873.6,105.5,180,-8,70
close_camera=650235,5401873.6,105.5,138,-12,18
for mode in splats shaded; do
    suffix=${mode/splats/}
    $bin/src/strata-view --headless "$work/street2m_normals.strata" --camera=$street_camera \
        --size 400x300 --pipeline $mode --out "$out/splats_street${suffix:+_$suffix}.png"
    $bin/src/strata-view --headless "$work/street2m_normals.strata" --camera=$close_camera \
        --size 480x360 --pipeline $mode --out "$out/splats_cars${suffix:+_$suffix}.png"
done
ls -la "$out"/splats_*
