#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Hole/background changes between neighbouring empty pixels of `strata-view --pipeline
# hpr` pictures, counted across 16- and 32-px block lines and across odd lines (the
# pairs strata-bench's gap_blocks_N compares, docs/BENCH.md), as counts and rates, not
# only their ratio: a change that removes isolated background specks lowers the odd
# lines' rate and raises the ratio although fewer changes lie on block lines (issue 15,
# part 2, sixteenth round: sparse surfaces). Colours: shaders/display.comp (background
# black, hole (0.1, 0.35, 0.1)); every other colour is a point.
# usage: /usr/bin/python3 bench/gap_changes.py LABELS.png...   (numpy, PIL)
import sys

import numpy as np
from PIL import Image

HOLE = (26, 89, 26)  # round(255 * (0.1, 0.35, 0.1))

for path in sys.argv[1:]:
    rgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.int16)
    background = rgb.sum(axis=2) == 0
    hole = np.all(np.abs(rgb - np.array(HOLE)) <= 1, axis=2)
    empty = background | hole
    out = [path]
    for block in (16, 32):
        counts = {}
        for axis in (1, 0):  # pairs (x, x + 1) across line x + 1, then (y, y + 1)
            a = [slice(None), slice(None)]
            b = [slice(None), slice(None)]
            a[axis] = slice(0, -1)
            b[axis] = slice(1, None)
            both = empty[tuple(a)] & empty[tuple(b)]
            change = both & (background[tuple(a)] != background[tuple(b)])
            line = np.arange(1, empty.shape[axis])
            for name, sel in (("odd", line % 2 == 1), ("block", line % block == 0)):
                take = np.take(both, np.nonzero(sel)[0], axis=axis).sum()
                changed = np.take(change, np.nonzero(sel)[0], axis=axis).sum()
                p, c = counts.get(name, (0, 0))
                counts[name] = (p + take, c + changed)
        (po, co), (pb, cb) = counts["odd"], counts["block"]
        out.append("%d px: block lines %d changes in %d pairs (%.5f), odd lines %d in %d "
                   "(%.5f), ratio %.2f" % (block, cb, pb, cb / pb, co, po, co / po,
                                          (cb / pb) / (co / po)))
    print("; ".join(out))
