#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Issue 12: the splat pass's two ways of drawing, instanced quads against a geometry
# shader on GL_POINTS, on the same synthetic splats (strata-splat-probe: a wall and a
# sphere, radius = lattice spacing, about pi splats per pixel), 1920x1080. For each size
# the methods alternate A B A B (ROUNDS rounds of REPEAT frames each); the probe prints
# the medians and their ratio. Every run goes to $BENCH_DIR/splat_methods_log.txt with
# the time and load average.
# usage: bench/splat_methods.sh      (SIZES="200000 1000000 4000000" ROUNDS=3 REPEAT=3)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/release}
[ -x $bin/src/bench/strata-splat-probe ] || { cmake --preset release >/dev/null && cmake --build --preset release -j >/dev/null; }
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
log=$work/splat_methods_log.txt
for n in ${SIZES:-200000 1000000 4000000}; do
    echo "== $n $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$log"
    $bin/src/bench/strata-splat-probe --points "$n" --width "${WIDTH:-1920}" \
        --height "${HEIGHT:-1080}" --rounds "${ROUNDS:-3}" --repeat "${REPEAT:-3}" | tee -a "$log"
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$log"

# The same on a converted scan: the 2 M-point street of bench/pictures.sh with --normals,
# the demo camera at 1920x1080, strata-view --pipeline splats, methods alternating
# (ROUNDS rounds), each run the median of REPEAT frames of the loaded view.
scene=$work/street2m_normals.strata
if [ ! -f "$scene" ]; then
    $bin/src/strata-synth street --points 2000000 --seed 1 -o "$work/street2m.las" --quiet
    $bin/preprocess/strata-convert "$work/street2m.las" -o "$scene" --normals --force -q
fi
camera=650235,5401873.6,105.5,180,-8,70
echo "== street2m_normals $(date -u +%FT%TZ) load $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$log"
for ((r = 0; r < ${ROUNDS:-3}; r++)); do
    for method in geometry instanced pulled; do
        line=$($bin/src/strata-view --headless "$scene" --camera=$camera --size 1920x1080 \
            --pipeline splats --splat-method $method --repeat "${REPEAT:-3}" --stats |
            grep '^median')
        echo "$method $line" | tee -a "$log"
    done
done
echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)" | tee -a "$log"
