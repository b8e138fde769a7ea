#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on a built-in sample: installs what is missing, builds Strata, makes a
# street scan with strata-synth, converts it to a .strata LOD hierarchy, verifies it
# and shows what it holds. (The viewer step joins this script when it lands.)
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
bin=build/release
mkdir -p out
"$bin/src/strata-synth" street --points 2000000 --seed 1 -o out/street.las
"$bin/preprocess/strata-convert" out/street.las -o out/street.strata --force
"$bin/src/strata-info" out/street.strata --verify
