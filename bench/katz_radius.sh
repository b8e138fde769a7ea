#!/bin/bash
# SPDX-License-Identifier: MIT
# Katz HPR against the ray-cast truth at several image sizes (docs/KATZ.md, "Choosing R"):
# street 1 M (one street view), sphere 200 k, nested 200 k and the bunny (mesh, 200 k; one
# orbit view), with R from sta_katz_view_radius, and with R per region (--katz-local,
# bench/katz_local.h). Prints one line per scene, size and variant: points, R, P / R / F1, ms.
# Usage: bench/katz_radius.sh [BUILD] [WORK]   (defaults build/release, /tmp/strata-katz)
set -euo pipefail
build=${1:-build/release}
work=${2:-/tmp/strata-katz}
mkdir -p "$work"
synth() { # scene points
    [ -f "$work/$1.strata" ] && return
    "$build/src/strata-synth" "$1" --points "$2" --seed 1 -o "$work/$1.las"
    "$build/preprocess/strata-convert" "$work/$1.las" -o "$work/$1.strata" --force >/dev/null
}
synth street 1M
synth sphere 200k
synth nested 200k
scenes="street sphere nested"
bunny=$(dirname "$0")/../../shared/data/models/bun_zipper.ply # Stanford bunny, if present
if [ -f "$bunny" ]; then
    if [ ! -f "$work/bunny.strata" ]; then
        "$build/src/strata-synth" mesh --mesh "$bunny" --points 200k --seed 1 -o "$work/bunny.las"
        "$build/preprocess/strata-convert" "$work/bunny.las" -o "$work/bunny.strata" --force >/dev/null
    fi
    scenes="$scenes bunny"
fi
for scene in $scenes; do
    views="--orbit 1"
    [ "$scene" = street ] && views="--street 1"
    for size in 480x270 960x540 1920x1080; do
        for variant in one-R local; do
            out="$work/$scene-$size-$variant"
            local_flag=""
            [ "$variant" = local ] && local_flag="--katz-local"
            # shellcheck disable=SC2086
            "$build/src/bench/strata-bench" $views --size "$size" --budgets all --pipelines hpr \
                --repeat 1 --katz $local_flag --no-image-error --quiet --out "$out" \
                "$work/$scene.strata"
            python3 - "$out/results.csv" "$scene" "$size" "$variant" <<'PY'
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
f = lambda k: float(r[k])
print(f"{sys.argv[2]:7s} {sys.argv[3]:10s} {sys.argv[4]:6s} points {r['katz_points']:>7s}"
      f" R {f('katz_radius_m'):10.4g} m  katz P {f('katz_precision'):.4f} R {f('katz_recall'):.4f}"
      f" F1 {f('katz_f1'):.4f}  ({f('katz_ms'):.0f} ms)  pyramid HPR F1 {f('hpr_f1'):.3f}")
PY
        done
    done
done
