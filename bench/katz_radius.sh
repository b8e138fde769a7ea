#!/bin/bash
# SPDX-License-Identifier: MIT
# Katz HPR against the ray-cast truth at several image sizes (docs/KATZ.md, "Choosing R"):
# street 1 M (one street view), sphere 200 k and nested 200 k (one orbit view), with R from
# sta_katz_view_radius. Prints one line per scene and size: points, R, P / R / F1, ms.
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
for scene in street sphere nested; do
    views="--orbit 1"
    [ "$scene" = street ] && views="--street 1"
    for size in 480x270 960x540 1920x1080; do
        out="$work/$scene-$size"
        # shellcheck disable=SC2086
        "$build/src/bench/strata-bench" $views --size "$size" --budgets all --pipelines hpr \
            --repeat 1 --katz --no-image-error --quiet --out "$out" "$work/$scene.strata"
        python3 - "$out/results.csv" "$scene" "$size" <<'PY'
import csv, sys
r = next(csv.DictReader(open(sys.argv[1])))
f = lambda k: float(r[k])
print(f"{sys.argv[2]:7s} {sys.argv[3]:10s} points {r['katz_points']:>7s} R {f('katz_radius_m'):10.4g} m"
      f"  katz P {f('katz_precision'):.3f} R {f('katz_recall'):.3f} F1 {f('katz_f1'):.3f}"
      f"  ({f('katz_ms'):.0f} ms)  pyramid HPR F1 {f('hpr_f1'):.3f}")
PY
    done
done
