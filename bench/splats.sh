#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Issue 12: splats as a method beside the screen-space pipeline in strata-bench's
# speed-against-error table. strata-synth scenes with known truth (sphere, planes,
# nested at ANALYTIC points, a street scan of STREET points) converted with --normals;
# strata-bench --pipelines shaded,splats on the same views (per view the two settings
# run one after the other: A B A B over the views), then a summary per scene and method:
# medians over the views of the frame time, the geometry (or splat) pass, the normal
# and depth errors, PSNR and SSIM against the all-points reference.
# usage: bench/splats.sh   (SIZE=960x540 VIEWS=4 REPEAT=3 ANALYTIC=200000 STREET=2000000
#                           BUDGET=1M; BENCH_DIR scratch)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
[ -x $bin/src/bench/strata-bench ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}/splats
mkdir -p "$work"
size=${SIZE:-960x540} views=${VIEWS:-4} repeat=${REPEAT:-3} budget=${BUDGET:-1M}

make_scene() { # NAME SCENE POINTS
    [ -f "$work/$1.strata" ] && return
    $bin/src/strata-synth "$2" --points "$3" -o "$work/$1.las" --quiet
    $bin/preprocess/strata-convert "$work/$1.las" -o "$work/$1.strata" --normals --force -q
}
make_scene sphere sphere "${ANALYTIC:-200000}"
make_scene planes planes "${ANALYTIC:-200000}"
make_scene nested nested "${ANALYTIC:-200000}"
make_scene street street "${STREET:-2000000}"

echo "start $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)"
for scene in sphere planes nested; do
    $bin/src/bench/strata-bench "$work/$scene.strata" --orbit "$views" --size "$size" \
        --budgets "$budget" --pipelines shaded,splats --repeat "$repeat" --quiet \
        --out "$work/out_$scene" >/dev/null
done
$bin/src/bench/strata-bench "$work/street.strata" --street "$views" --size "$size" \
    --budgets "$budget" --pipelines shaded,splats --repeat "$repeat" --quiet \
    --out "$work/out_street" >/dev/null
echo "end $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)"

python3 - "$work" <<'PY'
import csv, statistics, sys
work = sys.argv[1]
cols = ["frame_ms", "geometry_ms", "normal_mean_deg", "normal_median_deg", "normal_p95_deg",
        "depth_rel_median", "depth_rel_p95", "psnr_db", "ssim"]
print("| scene | method | " + " | ".join(cols) + " |")
print("|---" * (len(cols) + 2) + "|")
for scene in ["sphere", "planes", "nested", "street"]:
    rows = list(csv.DictReader(open(f"{work}/out_{scene}/results.csv")))
    for method in ["shaded", "splats"]:
        picked = [r for r in rows if r["pipeline"] == method]
        cells = []
        for c in cols:
            values = [float(r[c]) for r in picked if r[c] not in ("", "inf", "nan")]
            cells.append(f"{statistics.median(values):.4g}" if values else "-")
        print(f"| {scene} | {method} | " + " | ".join(cells) + " |")
PY
