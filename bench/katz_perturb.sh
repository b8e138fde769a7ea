#!/bin/bash
# SPDX-License-Identifier: MIT
# Braga et al.'s perturbation against the plain hull on the same input (docs/KATZ.md):
# strata-bench --katz --katz-perturbation A runs, per view, the perturbed and the plain
# hull on the same points interleaved (A B A B ... --repeat times) and reports both medians;
# the script prints their ratio and both F1 per scene and A. Also the live mode's hull
# (--katz-live, 50k-point subsample) with its plain twin on the same input.
# Usage: bench/katz_perturb.sh [BUILD] [WORK] [SIZE] [REPEAT]
#        (defaults build/release, /tmp/strata-katz, 960x540, 5)
set -euo pipefail
build=${1:-build/release}
work=${2:-/tmp/strata-katz}
size=${3:-960x540}
repeat=${4:-5}
mkdir -p "$work"
synth() { # name scene points [options]
    local name=$1 scene=$2 points=$3
    shift 3
    [ -f "$work/$name.strata" ] && return
    "$build/src/strata-synth" "$scene" --points "$points" --seed 1 -o "$work/$name.las" "$@"
    "$build/preprocess/strata-convert" "$work/$name.las" -o "$work/$name.strata" --force >/dev/null
}
synth street street 1M
synth sphere sphere 200k
synth nested nested 200k
bunny=$(dirname "$0")/../../shared/data/models/bun_zipper.ply
scenes="street sphere nested"
if [ -f "$bunny" ]; then
    synth bunny mesh 200k --mesh "$bunny"
    scenes="$scenes bunny"
fi
for scene in $scenes; do
    views="--orbit 1"
    [ "$scene" = street ] && views="--street 1"
    for a in 1e-5 1e-4 1e-3 1e-2; do
        out="$work/perturb-$scene-$a"
        # shellcheck disable=SC2086
        "$build/src/bench/strata-bench" $views --size "$size" --budgets all --pipelines raw \
            --repeat "$repeat" --katz --katz-live --katz-perturbation "$a" --no-image-error \
            --quiet --out "$out" "$work/$scene.strata"
        python3 - "$out/results.csv" "$scene" "$a" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
ref = rows[0]
live = next(r for r in rows if r["hpr"] == "katz-live")
f = lambda r, k: float(r[k])
print(f"{sys.argv[2]:7s} a={sys.argv[3]:5s} reference {ref['katz_points']:>7s} points: hull "
      f"{f(ref, 'katz_plain_hull_ms'):7.1f} ms plain, {f(ref, 'katz_hull_ms'):7.1f} ms perturbed "
      f"(x{f(ref, 'katz_plain_hull_ms') / f(ref, 'katz_hull_ms'):.2f}); F1 "
      f"{f(ref, 'katz_plain_f1'):.3f} -> {f(ref, 'katz_f1'):.3f} | live {live['katz_points']} "
      f"points: {f(live, 'katz_live_plain_hull_ms'):.1f} -> {f(live, 'hpr_ms'):.1f} ms")
PY
    done
done
