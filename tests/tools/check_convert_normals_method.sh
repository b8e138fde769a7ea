#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# strata-convert --normals-method: an unknown method is refused with a message naming the
# methods (exit 2, nothing written); each method converts, and the three methods give
# three different files (the option reaches the normals, not only the parser).
# usage: check_convert_normals_method.sh BUILD_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
mkdir -p "$work"
rm -f "$work"/*.strata
"$bin/src/strata-synth" sphere --points 20000 --seed 3 -o "$work/sphere.las" --quiet
set +e
message=$("$bin/preprocess/strata-convert" "$work/sphere.las" -o "$work/bogus.strata" \
    --normals --normals-method bogus 2>&1)
status=$?
set -e
echo "bogus: exit $status: $message"
[ "$status" = 2 ] || { echo "an unknown method did not exit 2" >&2; exit 1; }
[[ "$message" == *"moments, knn or moments-fine, got 'bogus'"* ]] ||
    { echo "the refusal does not name the methods and the value" >&2; exit 1; }
[ ! -e "$work/bogus.strata" ] || { echo "a refused conversion wrote a file" >&2; exit 1; }
for method in moments knn moments-fine; do
    "$bin/preprocess/strata-convert" "$work/sphere.las" -o "$work/$method.strata" --normals \
        --normals-method "$method" --force -q
done
if cmp -s "$work/moments.strata" "$work/knn.strata" ||
    cmp -s "$work/moments.strata" "$work/moments-fine.strata"; then
    echo "two methods wrote the same file" >&2
    exit 1
fi
echo "moments, knn and moments-fine: three different files"
