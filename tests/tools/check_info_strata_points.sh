#!/bin/sh
# SPDX-License-Identifier: MIT
# strata-info --points on a .strata file: the same rows as on its LAS input (as a
# multiset: the .strata order is the node table's), and START:COUNT windows in file
# order that tile the whole list.
# usage: check_info_strata_points.sh STRATA-INFO STRATA-CONVERT SHARED-DATA
set -eu
info=$1 convert=$2 data=$3
[ -d "$data" ] || { echo "shared data absent: $data"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for f in simple.las 1815.las simple1_4.las; do
    "$convert" -q "$data/las/$f" -o "$work/s.strata" --force
    "$info" --points 0:100000000 "$data/las/$f" | sort >"$work/las.csv"
    "$info" --points 0:100000000 "$work/s.strata" >"$work/strata.csv"
    sort "$work/strata.csv" | cmp - "$work/las.csv"
    # Windows: 0:500, 500:500, ... concatenated equal the whole list.
    total=$(($(wc -l <"$work/strata.csv") - 1))
    : >"$work/windows.csv"
    start=0
    while [ $start -lt $total ]; do
        "$info" --points $start:500 "$work/s.strata" | tail -n +2 >>"$work/windows.csv"
        start=$((start + 500))
    done
    tail -n +2 "$work/strata.csv" | cmp - "$work/windows.csv"
    [ "$total" -gt 0 ]
    echo "$f: $total points agree"
done
