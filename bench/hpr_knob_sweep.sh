#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Street HPR F1 (views 0 / 1 / 2, 960x540, the screen_quality.sh street scene) of one
# build under several settings given as environment knobs (issue 15, sixteenth round:
# a build with bench/patches/issue15_hpr_r16_knobs.patch applied; every knob off gives
# main's labels). One line per setting: its name, then F1 and the depth p95 under the
# glass rule per view. Deterministic on llvmpipe: one run per setting. With CLOSED=DIR
# (issue 15, seventeenth round: bench/patches/issue15_hpr_r17_knobs.patch) also the F1 of
# the two orbit views of DIR/nested.strata and DIR/bunny.strata at 640x480, as
# bench/screen_quality.sh runs them (its BENCH_DIR holds both), after a '|'.
# usage: bench/hpr_knob_sweep.sh BUILD SCENE.strata 'NAME|KNOB=V KNOB=V' ...
#   (BENCH_DIR: work folder, default /tmp/strata-knobs; EXTRA: more strata-bench options;
#    CLOSED: folder of the closed models' scenes, default none)
set -euo pipefail
build=$1 scene=$2
shift 2
work=${BENCH_DIR:-/tmp/strata-knobs}
mkdir -p "$work"
for setting in "$@"; do
    name=${setting%%|*}
    knobs=${setting#*|}
    [ "$knobs" = "$setting" ] && knobs=
    out="$work/out-$name"
    # shellcheck disable=SC2086
    env $knobs "$build/src/bench/strata-bench" "$scene" --street 3 --size 960x540 --repeat 1 \
        --no-image-error --pipelines normals --out "$out" --quiet ${EXTRA:-}
    awk -F, -v name="$name" '
        NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { line = line sprintf(" v%s %.4f (%.2f %%)", $col["camera"], $col["hpr_f1"],
                              100 * $col["depth_glass_rel_p95"]) }
        END { printf "%s:%s", name, line }' "$out/results.csv"
    for model in ${CLOSED:+nested bunny}; do
        # shellcheck disable=SC2086
        env $knobs "$build/src/bench/strata-bench" "$CLOSED/$model.strata" --orbit 2 \
            --size 640x480 --repeat 1 --no-image-error --pipelines normals \
            --out "$out-$model" --quiet ${EXTRA:-}
        awk -F, -v model="$model" '
            NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
            { line = line sprintf(" %.4f", $col["hpr_f1"]) }
            END { printf " | %s%s", model, line }' "$out-$model/results.csv"
    done
    echo
done
