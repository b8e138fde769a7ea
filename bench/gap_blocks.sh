#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Block artefacts of the hole-or-background decision (issue 15, part 2): strata-bench's
# gap_blocks_8 / _16 / _32 (docs/BENCH.md: how much more often hole and background change
# between neighbouring empty pixels across 8-, 16- and 32-px block lines than across odd
# lines; 1 = no block structure) on the street's three views at 960x540 and on the
# README's view at 1280x720 and 1920x1080, for one or more builds (deterministic on
# llvmpipe, so builds are compared by running them one after the other).
# usage: bench/gap_blocks.sh BUILD[:LABEL]...   (BENCH_DIR: work folder, default
#   /tmp/strata-gaps; SCENE: the 2 M-point street, made with the last build if absent;
#   EXTRA: more strata-bench options, e.g. --hpr-every-pixel; GAPS: the --hpr-gaps mode
#   of the builds that have it, default smooth, the per-pixel decision this measures)
set -euo pipefail
work=${BENCH_DIR:-/tmp/strata-gaps}
gaps_option() {
    local help
    help=$("$1/src/bench/strata-bench" --help)
    if [[ $help == *--hpr-gaps* ]]; then
        echo "--hpr-gaps ${GAPS:-smooth}"
    fi
}
mkdir -p "$work"
last=${!#}
last=${last%%:*}
scene=${SCENE:-$work/street2m.strata}
if [ ! -f "$scene" ]; then
    "$last/src/strata-synth" street --points 2000000 --seed 1 -o "$work/street2m.las" --quiet
    "$last/preprocess/strata-convert" "$work/street2m.las" -o "$scene" --force -q
fi
# The README's view (scripts/demo.sh) as a one-keyframe camera path.
cat > "$work/readme.json" <<'JSON'
{ "version": 1, "keyframes": [ { "time": 0, "position": [650235, 5401873.6, 105.5], "yaw": 180, "pitch": -8, "fov": 70 } ] }
JSON
for spec in "$@"; do
    build=${spec%%:*}
    label=${spec#*:}
    [ "$label" = "$spec" ] && label=$(basename "$build")
    for view in "street --street 3 960x540" "readme --path $work/readme.json 1280x720" \
        "readme --path $work/readme.json 1920x1080"; do
        read -r name opt arg size <<<"$view"
        out="$work/out-$label-$name-$size"
        # shellcheck disable=SC2086,SC2046 # options: several words
        "$build/src/bench/strata-bench" "$scene" $opt "$arg" --size "$size" --repeat 1 \
            --no-image-error --pipelines hpr --out "$out" --quiet $(gaps_option "$build") ${EXTRA:-}
        awk -F, -v label="$label" -v name="$name" -v size="$size" '
            NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
            { printf "%s %s %s view %s: hole/background changes on block lines / odd lines: 8 px %.2f, 16 px %.2f, 32 px %.2f\n",
                  label, name, size, $col["camera"], $col["gap_blocks_8"], $col["gap_blocks_16"],
                  $col["gap_blocks_32"] }' "$out/results.csv"
    done
done
