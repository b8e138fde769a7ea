#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Whether a change to strata-convert --normals kept its output: converts each input with a
# reference binary (e.g. main at the branch point, copied aside) and a new one, with every
# normals method and 1 and 2 threads, and compares the .strata files byte for byte (a
# speed change must not move a bit; an accuracy change shows up here on purpose).
#
#   bench/normals_same_bytes.sh REF_CONVERT NEW_CONVERT INPUT...
#
# METHODS="moments moments-fine knn" (default all three), THREADS="1 2",
# BENCH_DIR=/tmp/strata-same-bytes. Prints one line a run and exits 1 when any differ.
set -euo pipefail
[ $# -ge 3 ] || {
    sed -n '3,11p' "$0"
    exit 2
}
ref=$1 new=$2
shift 2
work=${BENCH_DIR:-/tmp/strata-same-bytes}
mkdir -p "$work"
status=0
for input in "$@"; do
    for method in ${METHODS:-moments moments-fine knn}; do
        for threads in ${THREADS:-1 2}; do
            args=(--normals --normals-method "$method" --threads "$threads" --force -q)
            "$ref" "$input" -o "$work/ref.strata" "${args[@]}"
            "$new" "$input" -o "$work/new.strata" "${args[@]}"
            if cmp -s "$work/ref.strata" "$work/new.strata"; then
                echo "same     $method, $threads threads: $input"
            else
                echo "DIFFERS  $method, $threads threads: $input"
                status=1
            fi
        done
    done
done
exit $status
