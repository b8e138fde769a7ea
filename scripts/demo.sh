#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The main job on a built-in sample: installs what is missing, builds Strata, makes a
# street scan with strata-synth and shows what it holds.
# (The viewer and converter steps join this script as they land.)
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
bin=build/release/src
mkdir -p out
"$bin/strata-synth" street --points 2000000 --seed 1 -o out/street.las
"$bin/strata-info" out/street.las
