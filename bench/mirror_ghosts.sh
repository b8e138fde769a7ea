#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Mirror ghosts (docs/MIRRORS.md): (1) precision and recall of both ghost models
# against the truth of `strata-synth mirror`, over seeds and origins; (2) the cost of
# `strata-convert --mirrors` against the same conversion without it, interleaved
# A B A B ... in one run, medians and spread.
# Usage: bash bench/mirror_ghosts.sh [build-dir] [points] [repeats]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
points="${2:-2M}"
repeats="${3:-5}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "== ghost models against the truth ($points points per scene)"
echo "seed origin model points ghosts tp fp fn wrong_mirror precision recall"
for seed in 1 2 3; do
    for origin in zero ecef; do
        "$build/tests/mirror_ghosts" --las "$work/room.las" --points "$points" --seed "$seed" \
            --origin "$origin" | grep -v '^ ' | sed "s/^/$seed $origin /"
    done
done
echo "== per mirror (seed 1, ecef)"
"$build/tests/mirror_ghosts" --las "$work/room.las" --points "$points" --seed 1 --origin ecef
echo "== strata-convert with and without --mirrors (seconds, interleaved)"
run() { # name, then convert options
    local start end
    start=$EPOCHREALTIME
    "$build/preprocess/strata-convert" -q --force "$work/room.las" -o "$work/out.strata" "${@:2}"
    end=$EPOCHREALTIME
    echo "$1 $(awk "BEGIN { print $end - $start }")"
}
for _ in $(seq "$repeats"); do
    run plain
    run mirrors --mirrors "$work/room.mirrors.json"
done | tee "$work/times"
python3 - "$work/times" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
t = {k: [float(r[1]) for r in rows if r[0] == k] for k in ("plain", "mirrors")}
for k in ("plain", "mirrors"):
    print(f"{k}: median {statistics.median(t[k]):.3f} s, spread {min(t[k]):.3f}..{max(t[k]):.3f} s")
ratios = [b / a for a, b in zip(t["plain"], t["mirrors"])]
print(f"--mirrors / plain: median of pair ratios {statistics.median(ratios):.3f} "
      f"(pairs {min(ratios):.3f}..{max(ratios):.3f})")
PY
