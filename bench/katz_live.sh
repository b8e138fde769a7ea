#!/bin/bash
# SPDX-License-Identifier: MIT
# The live Katz mode's latency against F1 (docs/KATZ.md, "Live mode"; docs/BENCHMARKS.md):
# strata-bench --katz-live on the 1 M street (street view 0) for several --katz-points and
# --katz-oversample settings, the settings interleaved round by round (A B C A B C ...),
# medians per setting. Prints one line per setting.
# Usage: bench/katz_live.sh [BUILD] [WORK] [SIZE] [ROUNDS] [SETTINGS...]
#   (defaults build/release, /tmp/strata-katz, 960x540, 3, and the settings below;
#    a setting is POINTS:OVERSAMPLE)
set -euo pipefail
build=${1:-build/release}
work=${2:-/tmp/strata-katz}
size=${3:-960x540}
rounds=${4:-3}
shift $(($# < 4 ? $# : 4))
settings=("$@")
[ ${#settings[@]} -gt 0 ] || settings=(12500:8 25000:8 50000:8 100000:8 50000:1 50000:4 50000:16)
mkdir -p "$work"
if [ ! -f "$work/street.strata" ]; then
    "$build/src/strata-synth" street --points 1M --seed 1 -o "$work/street.las"
    "$build/preprocess/strata-convert" "$work/street.las" -o "$work/street.strata" --force >/dev/null
fi
rows="$work/katz_live_rows.txt"
: >"$rows"
for round in $(seq "$rounds"); do
    for setting in "${settings[@]}"; do
        points=${setting%%:*}
        oversample=${setting##*:}
        out="$work/katz-live-$points-$oversample"
        "$build/src/bench/strata-bench" --street 1 --size "$size" --budgets all --pipelines hpr \
            --repeat 1 --katz-live --katz-points "$points" --katz-oversample "$oversample" \
            --no-image-error --quiet --out "$out" "$work/street.strata" >/dev/null
        python3 - "$out/results.csv" "$setting" "$round" >>"$rows" <<'PY'
import csv, sys
for r in csv.DictReader(open(sys.argv[1])):
    if r["hpr"] == "katz-live":
        print(sys.argv[2], sys.argv[3], r["katz_points"], r["hpr_precision"], r["hpr_recall"],
              r["hpr_f1"], r["katz_live_latency_ms"], r["hpr_ms"], r["katz_live_hull_cpu_ms"])
PY
    done
done
python3 - "$rows" "${settings[@]}" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
print(f"{'points:oversample':18s} {'hull pts':>8s} {'P':>6s} {'R':>6s} {'F1':>6s}"
      f" {'latency ms':>18s} {'hull ms':>8s} {'cpu ms':>7s}")
for s in sys.argv[2:]:
    mine = [r for r in rows if r[0] == s]
    med = lambda i: statistics.median(float(r[i]) for r in mine)
    lat = sorted(float(r[6]) for r in mine)
    print(f"{s:18s} {med(2):8.0f} {med(3):6.3f} {med(4):6.3f} {med(5):6.3f}"
          f" {med(6):6.0f} ({lat[0]:.0f}-{lat[-1]:.0f}) {med(7):8.0f} {med(8):7.0f}")
PY
