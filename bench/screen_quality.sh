#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Screen-space picture error against the synth's truth (issue 15, parts 2 and 3): HPR
# F1, filled-depth p95 (relative; all pixels with a truth hit, and only those of a sampled
# surface, strata-bench's depth_sampled_*; and over those with window glass accepted as a
# surface, depth_glass_*) and pyramidal normal median / p95 on the three street
# views (960x540, 2 M points, seed 1) and two orbit views of sphere, nested and the
# bunny (640x480, 200 k points, seed 1); since issue 15's fourteenth round also the F1
# under the face rule and the face and glass rules (hpr_face_f1, hpr_face_glass_f1) and
# the normals under the face rule (normal_face_*; docs/BENCH.md); since issue 15's fifteenth
# round the share of normals off by more than 30 degrees, split by the true face's
# orientation (normal_off_*: facing the camera or not); since the sixteenth round the part
# of that share whose filled depth is off by more than the truth tolerance (normal_off_fill_share:
# the fill's, not the estimator's), the share of pixels without a normal (unknown, shaded
# flat) and the errors as shaded, the unknown ones lit as facing the camera
# (normal_unknown_share, normal_shaded_*); since the nineteenth round the F1 under the
# volumetric rule (hpr_volumetric_f1). strata-bench runs the
# viewer's volumetric classes; EXTRA=--fill-every-class gives the measure before. One
# line per view; errors are deterministic on llvmpipe, so two builds are compared by
# running the script once per build.
# usage: bench/screen_quality.sh [BUILD=build/release] [LABEL]
#   (EXTRA: more strata-bench options; BENCH_DIR: work folder, default /tmp/strata-quality;
#    BUNNY: the bunny PLY, default ../shared/data/models/bun_zipper.ply; DRAGON: the
#    dragon OBJ, default ../shared/data/models/dragon_vrip_res3.obj, since issue 15's
#    twenty-first round, standing on +Z as the synth now stands y-up models)
set -euo pipefail
build=${1:-build/release}
label=${2:-$(basename "$build")}
work=${BENCH_DIR:-/tmp/strata-quality}
bunny=${BUNNY:-$(dirname "$0")/../../shared/data/models/bun_zipper.ply}
dragon=${DRAGON:-$(dirname "$0")/../../shared/data/models/dragon_vrip_res3.obj}
mkdir -p "$work"
synth=$build/src/strata-synth
convert=$build/preprocess/strata-convert
bench=$build/src/bench/strata-bench
make_scene() { # name, synth arguments...
    local name=$1
    shift
    if [ ! -f "$work/$name.strata" ]; then
        "$synth" "$@" --seed 1 -o "$work/$name.las" --quiet
        "$convert" "$work/$name.las" -o "$work/$name.strata" --force -q
    fi
}
make_scene street street --points 2000000
make_scene sphere sphere --points 200000
make_scene nested nested --points 200000
make_scene bunny mesh --mesh "$bunny" --points 200000
make_scene dragon mesh --mesh "$dragon" --points 200000
run() { # scene, views option, size
    local out="$work/out-$label-$1"
    # shellcheck disable=SC2086
    "$bench" "$work/$1.strata" $2 --size "$3" --repeat 1 --no-image-error \
        --pipelines normals --out "$out" --quiet ${EXTRA:-}
    awk -F, -v label="$label" -v scene="$1" '
        NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
        { glass = ("depth_glass_rel_p95" in col) ? sprintf("%.2f %%", 100 * $col["depth_glass_rel_p95"]) : "n/a"
          face_f1 = ("hpr_face_f1" in col) ? sprintf("%.4f / %.4f", $col["hpr_face_f1"], $col["hpr_face_glass_f1"]) : "n/a"
          if ("hpr_volumetric_f1" in col)
              face_f1 = face_f1 sprintf("; volumetric rule %.4f", $col["hpr_volumetric_f1"])
          face_n = ("normal_face_p95_deg" in col) ? sprintf("%.2f / %.1f", $col["normal_face_median_deg"], $col["normal_face_p95_deg"]) : "n/a"
          off = ("normal_off_share" in col) ? sprintf(", off > 30 deg %.2f %% (facing %.2f %%, other %.2f %%; face rule %.2f %%)",
              100 * $col["normal_off_share"], 100 * $col["normal_off_facing_share"],
              100 * $col["normal_off_other_share"], 100 * $col["normal_face_off_share"]) : ""
          fill = ("normal_off_fill_share" in col) ? sprintf(", of them with the fill off %.2f %%", 100 * $col["normal_off_fill_share"]) : ""
          if ("normal_unknown_share" in col)
              fill = fill sprintf("; unknown %.2f %%, as shaded %.2f / %.1f deg, off %.2f %%",
                  100 * $col["normal_unknown_share"], $col["normal_shaded_median_deg"],
                  $col["normal_shaded_p95_deg"], 100 * $col["normal_shaded_off_share"])
          printf "%s %s view %s: F1 %.4f (face rule, + glass: %s) depth p95 %.2f %% (sampled %.2f %%, glass rule %s) normals %.2f / %.1f deg (face rule %s)%s%s\n",
              label, scene, $col["camera"], $col["hpr_f1"], face_f1, 100 * $col["depth_rel_p95"],
              100 * $col["depth_sampled_rel_p95"], glass,
              $col["normal_median_deg"], $col["normal_p95_deg"], face_n, off, fill }' "$out/results.csv"
}
run street "--street 3" 960x540
for scene in sphere nested bunny dragon; do
    run $scene "--orbit 2" 640x480
done
