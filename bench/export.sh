#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-export speed: the whole scene (A) against a box over a quarter of its plan
# area (B), interleaved A B A B ... in one run, medians and spread. The scene is the
# four lasR forest tiles (2.83 M points, LAZ) merged by strata-convert.
# Usage: bash bench/export.sh [build-dir] [repeats]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
repeats="${2:-5}"
data="$root/../shared/data/laz-tiles"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/preprocess/strata-convert" -q "$data"/bcts_*.laz -o "$work/forest.strata"
# The quarter box: the lower-left quarter of the scene's bounds in x and y.
read -r x0 y0 z0 x1 y1 z1 < <("$build/src/strata-info" --json "$work/forest.strata" |
    python3 -c 'import json,sys; j=json.load(sys.stdin); lo=j["bounds_min"]; hi=j["bounds_max"];
print(lo[0], lo[1], lo[2], (lo[0]+hi[0])/2, (lo[1]+hi[1])/2, hi[2])')
box="$x0,$y0,$z0,$x1,$y1,$z1"
run() { # name, then export options; prints seconds and points
    local start end
    start=$EPOCHREALTIME
    "$build/src/strata-export" "$work/forest.strata" -o "$work/out.las" --force "${@:2}" \
        2>"$work/log"
    end=$EPOCHREALTIME
    echo "$1 $(awk "BEGIN { print $end - $start }") $(grep -o '[0-9]* points' "$work/log" | head -1)"
}
for i in $(seq "$repeats"); do
    run whole
    run box --box "$box"
done | tee "$work/times"
python3 - "$work/times" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
t = {k: [float(r[1]) for r in rows if r[0] == k] for k in ("whole", "box")}
n = {k: int(next(r[2] for r in rows if r[0] == k)) for k in ("whole", "box")}
for k in ("whole", "box"):
    m = statistics.median(t[k])
    print(f"{k}: {n[k]} points, median {m:.3f} s ({n[k] / m / 1e6:.2f} M points/s), "
          f"spread {min(t[k]):.3f}..{max(t[k]):.3f} s")
ratios = [b / w for w, b in zip(t["whole"], t["box"])]
print(f"box / whole time: median {statistics.median(ratios):.3f} "
      f"(pairs {min(ratios):.3f}..{max(ratios):.3f}); points ratio {n['box'] / n['whole']:.3f}")
PY
