#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The README view's near wall, shaded, at 960x540, 1280x720 and 1920x1080 for builds
# given as BUILD:LABEL (issue 15, part 2, sixteenth round: sparse surfaces under the
# per-pixel gaps), then bench/sparse_wall.py's black-pixel counts (the first build is
# the reference for "turned black" / "filled"). Deterministic on llvmpipe.
# usage: bench/sparse_wall.sh SCENE.strata BUILD[:LABEL]...   (BENCH_DIR: work folder,
#   default /tmp/strata-sparse-wall; EXTRA: more strata-view options for every build)
set -euo pipefail
scene=$1
shift
work=${BENCH_DIR:-/tmp/strata-sparse-wall}
mkdir -p "$work"
camera=650235,5401873.6,105.5,180,-8,70
for size in 960x540 1280x720 1920x1080; do
    pngs=()
    for spec in "$@"; do
        build=${spec%%:*}
        label=${spec#*:}
        [ "$label" = "$spec" ] && label=$(basename "$build")
        out="$work/$label-$size.png"
        # shellcheck disable=SC2086 # EXTRA: several words
        "$build/src/strata-view" --headless "$scene" --camera=$camera --size "$size" \
            --out "$out" ${EXTRA:-}
        pngs+=("$out")
    done
    /usr/bin/python3 "$(dirname "$0")/sparse_wall.py" "${pngs[@]}"
done
