#!/usr/bin/env bash
# LAZ decoding speed by item version and layout, all in one run (ratios are what count
# on a shared machine): a 1 M point strata-synth street as PDRF 3 (point10 family,
# items version 1 and 2) and PDRF 7 (point14 family, version 3 and 4; one scanner
# channel, and two interleaved every 64 points), chunks of 50 000 and 1 000 points.
# The LAZ files are made by the test suite's encoder (tests/lazenc, never installed).
# Usage: bash bench/laz_versions.sh [build-dir]   (a Release build with tests)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build/release}"
lazenc="$build/tests/lazenc"
synth="$(find "$build" -name strata-synth -type f | head -1)"
[ -x "$lazenc" ] && [ -n "$synth" ] || { echo "laz_versions.sh: build $build first (tests on)" >&2; exit 1; }
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$synth" street -o "$work/p3.las" --points 1M --format 3 --quiet
"$synth" street -o "$work/p7.las" --points 1M --format 7 --quiet
enc() { "$lazenc" encode "$@" >/dev/null; }
enc "$work/p3.las" "$work/p3-v2.laz" --version 2
enc "$work/p3.las" "$work/p3-v1.laz" --version 1
enc "$work/p3.las" "$work/p3-v2-c1000.laz" --version 2 --chunk 1000
enc "$work/p7.las" "$work/p7-v3.laz" --version 3
enc "$work/p7.las" "$work/p7-v4.laz" --version 4
enc "$work/p7.las" "$work/p7-v3-2ch.laz" --version 3 --channels 2
enc "$work/p7.las" "$work/p7-v4-2ch.laz" --version 4 --channels 2
enc "$work/p7.las" "$work/p7-v3-c1000.laz" --version 3 --chunk 1000
echo "file sizes (bytes): $(cd "$work" && stat -c '%n %s' *.laz | tr '\n' ' ')"
echo "decoding, one thread, best of 3 (lazenc time):"
"$lazenc" time "$work"/p3-v2.laz "$work"/p3-v1.laz "$work"/p3-v2-c1000.laz \
    "$work"/p7-v3.laz "$work"/p7-v4.laz "$work"/p7-v3-2ch.laz "$work"/p7-v4-2ch.laz \
    "$work"/p7-v3-c1000.laz | sed "s|$work/||"
