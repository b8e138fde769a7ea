#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on a built-in sample: installs what is missing, builds Strata, makes a
# 2-million-point street scan with strata-synth, converts it to a .strata LOD hierarchy,
# checks it, and opens it in the viewer — or, without a display, renders it headless
# to out/street.png (and the raw points to out/street_raw.png).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
bin=build/release
mkdir -p out
"$bin/src/strata-synth" street --points 2000000 --seed 1 -o out/street.las
"$bin/preprocess/strata-convert" out/street.las -o out/street.strata --force
"$bin/src/strata-info" out/street.strata --verify | tail -12
# Standing on the road, 2.2 m up, looking down the street.
camera=650235,5401873.6,105.5,180,-8,70
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
    exec "$bin/src/strata-view" out/street.strata --camera=$camera
fi
"$bin/src/strata-view" --headless out/street.strata --camera=$camera --size 1280x720 \
    --out out/street.png --stats | tail -2
"$bin/src/strata-view" --headless out/street.strata --camera=$camera --size 1280x720 \
    --pipeline raw --out out/street_raw.png
echo "no display: rendered out/street.png (shaded) and out/street_raw.png (points)"
