#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The viewer's absolute figures on a GPU machine: frame and pass times at the 30 M
# budget, 1920x1080, on a strata-synth street of POINTS points (default 40 M, so that the
# README's street view at --min-spacing 0.1 wants more than the budget). Every setting
# runs once per round, the settings interleaved (A B C ... A B C ...), ROUNDS rounds;
# each run prints the median of REPEAT frames of the loaded view, the table gives the
# median over the rounds. Also: conversion wall times (plain and --normals), the view's
# load time, and pictures of the big scene (shaded, splats) and of the demo street with
# each rasteriser (same-picture check against llvmpipe, done where the PNGs land).
#
#   bench/gpu_figures.sh            (POINTS=40000000 ROUNDS=3 REPEAT=9 SIZE=1920x1080
#                                    BIN=build/release BENCH_DIR=/tmp/strata-gpu
#                                    PICTURES=dir for the PNGs and the log
#                                    PARTS="rounds default pictures bench")
#
# PARTS: rounds (the interleaved settings), default (the view at the default LOD: shaded
# and each splat method), pictures, bench (strata-bench on three street views with the
# truth: frame time against HPR F1, depth and normal error, results.csv in PICTURES).
#
# BIN is a build folder (src/, preprocess/, src/bench/) or one folder holding the
# programs. On a machine without a GPU it runs on llvmpipe (slowly: use POINTS=2000000).
set -uo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
work=${BENCH_DIR:-/tmp/strata-gpu}
points=${POINTS:-40000000}
rounds=${ROUNDS:-3}
repeat=${REPEAT:-9}
size=${SIZE:-1920x1080}
pictures=${PICTURES:-$work/pictures}
mkdir -p "$work" "$pictures"
log=$pictures/gpu_log.txt

exe() {
    local d
    for d in "$bin" "$bin/src" "$bin/preprocess" "$bin/src/bench"; do
        [ -x "$d/$1" ] && { echo "$d/$1"; return; }
    done
    echo "gpu_figures: no $1 under $bin" >&2
    exit 1
}
view=$(exe strata-view)
synth=$(exe strata-synth)
convert=$(exe strata-convert)
camera=650235,5401873.6,105.5,180,-8,70 # the README's street view (scripts/demo.sh)

say() { echo "$*" | tee -a "$log"; }
say "== $(date -u +%FT%TZ) $(nproc) cores; points $points rounds $rounds repeat $repeat size $size"
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader | tee -a "$log"

las=$work/street$points.las
plain=$work/street$points.strata
normals=$work/street${points}n.strata
if [ ! -f "$plain" ] || [ ! -f "$normals" ]; then
    t0=$(date +%s.%N)
    "$synth" street --points "$points" --seed 1 -o "$las" --quiet || exit 1
    t1=$(date +%s.%N)
    "$convert" "$las" -o "$plain" --force -q || exit 1
    t2=$(date +%s.%N)
    "$convert" "$las" -o "$normals" --force -q --normals || exit 1
    t3=$(date +%s.%N)
    say "$(python3 -c "print('synth %.1f s, convert %.1f s, convert --normals %.1f s (%.2fx)' % ($t1-$t0, $t2-$t1, $t3-$t2, ($t3-$t2)/($t2-$t1)))")"
fi

# name|scene|options: the settings of one round
settings=(
    "raw-compute|$plain|--pipeline raw"
    "raw-compute-32bit|$plain|--pipeline raw --raster-32bit"
    "raw-points|$plain|--pipeline raw --raster points"
    "shaded|$plain|--pipeline shaded"
    "shaded-32bit|$plain|--pipeline shaded --raster-32bit"
    "shaded-exhaustive-hpr|$plain|--pipeline shaded --hpr exhaustive"
    "edl|$plain|--pipeline edl"
    "splats-geometry|$normals|--pipeline splats --splat-method geometry"
    "splats-instanced|$normals|--pipeline splats --splat-method instanced"
    "splats-pulled|$normals|--pipeline splats --splat-method pulled"
)
parts=${PARTS:-rounds default pictures bench}
has() { case " $parts " in *" $1 "*) return 0 ;; esac; return 1; }
has rounds || rounds=0
for ((r = 1; r <= rounds; r++)); do
    for s in "${settings[@]}"; do
        IFS='|' read -r name scene options <<<"$s"
        # shellcheck disable=SC2086
        "$view" --headless "$scene" --camera=$camera --size "$size" --budget 30000000 \
            --gpu-mem 16384 --min-spacing 0.1 --repeat "$repeat" --stats $options >"$work/run.txt" 2>&1
        rc=$?
        grep -E '^(geometry pass|renderer|view loaded|median of)' "$work/run.txt" | sed "s/^/$r $name: /" >>"$log"
        [ $rc -eq 0 ] || { say "$r $name: exit $rc"; tail -5 "$work/run.txt" | tee -a "$log"; }
    done
done
# The user's view: default LOD (0.75 px spacing), default budget.
if has default; then
    for s in "shaded|$plain|--pipeline shaded" "splats-geometry|$normals|--pipeline splats" \
        "splats-instanced|$normals|--pipeline splats --splat-method instanced" \
        "splats-pulled|$normals|--pipeline splats --splat-method pulled"; do
        IFS='|' read -r name scene options <<<"$s"
        # shellcheck disable=SC2086
        "$view" --headless "$scene" --camera=$camera --size "$size" --repeat "$repeat" --stats \
            --gpu-mem 16384 $options 2>&1 | grep -E '^(view loaded|median of)' |
            sed "s/^/default-lod $name: /" | tee -a "$log"
    done
fi

python3 - "$log" <<'PY'
import re, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    m = re.match(r'(\d+) (\S+): median of \d+ frames: (.*)', line)
    if not m:
        continue
    times = dict((k, float(v)) for k, v in re.findall(r'(\w+) ([0-9.]+) ms', m.group(3)))
    drawn = re.search(r'(\d+) points drawn', m.group(3))
    times['drawn'] = float(drawn.group(1)) / 1e6 if drawn else float('nan')
    rows.setdefault(m.group(2), []).append(times)
keys = ['drawn', 'frame', 'geometry', 'unproject', 'hpr', 'pullpush', 'normals', 'shade', 'splats', 'vegetation']
present = [k for k in keys if any(k in t for runs in rows.values() for t in runs)]
print('| setting | rounds | ' + ' | '.join(('drawn (M)' if k == 'drawn' else k + ' ms') for k in present) + ' | screen passes / geometry |')
print('|---' * (len(present) + 3) + '|')
for name, runs in rows.items():
    med = {k: statistics.median(t[k] for t in runs if k in t) for k in present if any(k in t for t in runs)}
    screen = sum(med.get(k, 0) for k in ('unproject', 'hpr', 'pullpush', 'normals', 'shade', 'vegetation'))
    ratio = screen / med['geometry'] if med.get('geometry') else float('nan')
    cells = [('%.2f' % med[k]) if k in med else '' for k in present]
    print('| %s | %d | %s | %.2f |' % (name, len(runs), ' | '.join(cells), ratio))
PY

if has pictures; then
    # Pictures: the big scene as measured, and the demo street (2 M points) with each
    # rasteriser, to compare with llvmpipe's pictures of the same command pixel for pixel.
    "$view" --headless "$plain" --camera=$camera --size "$size" --budget 30000000 --gpu-mem 16384 \
        --min-spacing 0.1 --out "$pictures/shaded_big.png" >/dev/null 2>&1
    "$view" --headless "$normals" --camera=$camera --size "$size" --budget 30000000 --gpu-mem 16384 \
        --min-spacing 0.1 --pipeline splats --out "$pictures/splats_big.png" >/dev/null 2>&1
    demo=$work/demo.strata
    if [ ! -f "$demo" ]; then
        "$synth" street --points 2000000 --seed 1 -o "$work/demo.las" --quiet &&
            "$convert" "$work/demo.las" -o "$demo" --force -q
    fi
    for raster in "compute" "compute --raster-32bit" "points"; do
        # shellcheck disable=SC2086
        "$view" --headless "$demo" --camera=$camera --size "$size" --pipeline raw --raster $raster \
            --out "$pictures/demo_raw_${raster//[ -]/}.png" 2>&1 | grep -E '^geometry pass' >>"$log"
    done
    "$view" --headless "$demo" --camera=$camera --size "$size" --out "$pictures/demo_shaded.png" >/dev/null 2>&1
fi
# strata-bench: three street views with the truth (strata-synth's sidecar beside the scene).
if has bench; then
    cp "$work/street$points.truth.json" "$work/street${points}n.truth.json" 2>/dev/null
    bench=$(exe strata-bench)
    timeout "${BENCH_TIMEOUT:-300}" "$bench" "$normals" --street 3 --size "$size" \
        --pipelines raw,shaded,splats --repeat "$repeat" --out "$work/bench" --quiet >>"$log" 2>&1
    say "strata-bench exit $?"
    cp "$work/bench/results.csv" "$pictures/bench_results.csv" 2>/dev/null
fi
ls -la "$pictures" >>"$log"
