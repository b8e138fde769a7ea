#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One screen-space pass's time, round by round, for two builds interleaved A B A B ... at
# 1920x1080 on the README's street view (issue 15, fourteenth round: HPR's marked-point
# rule): per round each side's median of 5 frames (CPU clock), the load average, and at
# the end both medians and B/A per round, so that a small change can be told from the
# machine's noise by its direction in every round.
# usage: bench/pass_rounds.sh BUILD_A BUILD_B SCENE.strata [ROUNDS=7] [PASS=hpr]
#   (BUILD_*: release build folders holding src/strata-view; CLOCK: cpu or wall)
set -euo pipefail
a=$1 b=$2 scene=$3 rounds=${4:-7} pass=${5:-hpr}
camera=650235,5401873.6,105.5,180,-8,70
out=$(mktemp)
for r in $(seq "$rounds"); do
    for side in a b; do
        bin=$a
        [ $side = b ] && bin=$b
        line=$("$bin/src/strata-view" --headless "$scene" --camera=$camera --size 1920x1080 \
            --repeat 5 --stats --raster points --pipeline shaded --stats-clock "${CLOCK:-cpu}" |
            grep '^median')
        ms=$(grep -o "$pass [0-9.]* ms" <<<"$line" | awk '{print $2}')
        load=$(cut -d' ' -f1 /proc/loadavg)
        echo "$r $side $ms $load" | tee -a "$out"
    done
done
python3 - "$out" "$pass" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
a = [float(r[2]) for r in rows if r[1] == 'a']
b = [float(r[2]) for r in rows if r[1] == 'b']
print('%s median A %.1f B %.1f ms, B/A %.3f; per round %s; load %s-%s' % (
    sys.argv[2], statistics.median(a), statistics.median(b),
    statistics.median(b) / statistics.median(a), ' '.join('%.3f' % (y / x) for x, y in zip(a, b)),
    min(r[3] for r in rows), max(r[3] for r in rows)))
PY
rm -f "$out"
