#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-convert's command line: --compress 0 stores payloads uncompressed, the default
# compresses (zero-means-default inside, STA_CONVERT_STORE for "store").
# usage: check_convert_cli.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
mkdir -p "$work"
"$bin/src/strata-synth" sphere --points 20000 --seed 3 -o "$work/sphere.las" --quiet
"$bin/preprocess/strata-convert" "$work/sphere.las" -o "$work/stored.strata" --compress 0 --force -q
"$bin/preprocess/strata-convert" "$work/sphere.las" -o "$work/default.strata" --force -q
stored=$("$bin/src/strata-info" "$work/stored.strata" | grep -o 'compression [0-9.]*x')
default=$("$bin/src/strata-info" "$work/default.strata" | grep -o 'compression [0-9.]*x')
echo "--compress 0: $stored; default: $default"
[ "$stored" = "compression 1.00x" ] || { echo "--compress 0 did not store uncompressed" >&2; exit 1; }
[ "$default" != "compression 1.00x" ] || { echo "the default did not compress" >&2; exit 1; }
