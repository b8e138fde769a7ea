#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Headless renders of the demo scene (scripts/demo.sh's street and camera, smaller) in
# every pipeline and colour mode (compute rasteriser, the default; GL_POINTS for a few),
# compared with the SHA-256 of the PNGs recorded in tests/golden/renders.sha256. Restructuring must not change a pixel; a change that is
# meant to alter pictures re-records the list with --update (and says so in its commit).
# usage: check_golden_renders.sh BUILD_DIR HASH_FILE WORK_DIR [--update]
set -euo pipefail
bin=$1 hashes=$2 work=$3 update=${4:-}
mkdir -p "$work"
"$bin/src/strata-synth" street --points 1500000 --seed 1 -o "$work/street.las" >/dev/null
"$bin/preprocess/strata-convert" "$work/street.las" -o "$work/street.strata" --force >/dev/null 2>&1
camera=650235,5401873.6,105.5,180,-8,70
cases=(
    "raw_rgb --pipeline raw --colour rgb"
    "raw_intensity --pipeline raw --colour intensity"
    "raw_elevation --pipeline raw --colour elevation"
    "raw_class --pipeline raw --colour class"
    "raw_returns --pipeline raw --colour returns"
    "raw_height --pipeline raw --colour height"
    "raw_budget --pipeline raw --budget 60000"
    "overview --pipeline raw --default-camera"
    "edl --pipeline edl"
    "hpr --pipeline hpr"
    "hpr_exhaustive --pipeline hpr --hpr exhaustive"
    "fill --pipeline fill"
    "normals_pyramid --pipeline normals"
    "normals_pc_smooth --pipeline normals --normals pc --smooth"
    "shaded --pipeline shaded"
    "shaded_ld --pipeline shaded --normals ld"
    "points_rgb --pipeline raw --colour rgb --raster points"
    "points_class --pipeline raw --colour class --raster points"
    "points_shaded --pipeline shaded --raster points"
    "raw_3px --pipeline raw --point-size 3"
    "edl_adaptive --pipeline edl --point-size adaptive"
    "points_3px --pipeline raw --point-size 3 --raster points"
)
actual="$work/renders.sha256"
: >"$actual"
for entry in "${cases[@]}"; do
    read -r name args <<<"$entry"
    cam=(--camera=$camera)
    if [[ $args == *--default-camera* ]]; then
        cam=()
        args=${args/--default-camera/}
    fi
    # shellcheck disable=SC2086
    "$bin/src/strata-view" --headless "$work/street.strata" "${cam[@]}" --size 480x270 \
        $args --out "$work/$name.png" >/dev/null
    (cd "$work" && sha256sum "$name.png") >>"$actual"
done
if [ "$update" = "--update" ]; then
    cp "$actual" "$hashes"
    echo "recorded $(wc -l <"$hashes") render hashes in $hashes"
    exit 0
fi
if ! diff <(sort -k2 "$hashes") <(sort -k2 "$actual"); then
    echo "renders differ from $hashes (images in $work)" >&2
    exit 1
fi
echo "all $(wc -l <"$actual") renders match $hashes"
