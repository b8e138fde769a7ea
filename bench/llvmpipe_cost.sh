#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# What one compute-shader operation costs on the GL driver in use, headless (issue 15,
# fourteenth cost round; bench/llvmpipe_cost.c): image loads against texel fetches,
# RGBA32F stores against narrower ones and against a storage buffer's (with its copy into a
# texture: the staged stores), per-lane atomics, a tiny dispatch. CPU ms of a
# 1920x1080 dispatch, median of REPEATS (default 9), the probes interleaved.
# usage: bench/llvmpipe_cost.sh [REPEATS]   (BENCH_DIR: where the program is built)
set -euo pipefail
work=${BENCH_DIR:-/tmp/strata-bench}
mkdir -p "$work"
cc -O2 -Wall -Wextra -o "$work/llvmpipe_cost" "$(dirname "$0")/llvmpipe_cost.c" -lepoxy
EGL_PLATFORM=${EGL_PLATFORM:-surfaceless} "$work/llvmpipe_cost" "${1:-9}"
