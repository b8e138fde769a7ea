#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Where HPR errs on a closed model (issue 15, twenty-second round): from the per-pixel
# dumps of bench/patches/issue15_pixel_dump.patch (STA_BENCH_DUMP=DIR strata-bench ...),
# per view, the false positives' depth behind the truth (relative), the radius within
# which nearer drawn points (by more than 1 % of the depth) close all 8 sectors around
# them, and the false negatives that have a drawn point nearer by more than 3 s0 within
# 3 / 8 px (points beside an occluding edge) and their distance to the background.
# usage: /usr/bin/python3 bench/hpr_model_errors.py DUMP_DIR S0_M   (numpy, scipy)
import glob
import os
import sys

import numpy as np
from scipy import ndimage

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from screen_classes import load  # noqa: E402


def closing_radius(lab, depth, y, x, max_r=11):
    h, w = lab.shape
    z = depth[y, x]
    for r in range(1, max_r + 1):
        y0, y1, x0, x1 = max(0, y - r), min(h, y + r + 1), max(0, x - r), min(w, x + r + 1)
        m = ((lab[y0:y1, x0:x1] == 1) | (lab[y0:y1, x0:x1] == 2)) & (depth[y0:y1, x0:x1] < 0.99 * z)
        yy, xx = np.nonzero(m)
        if len(yy) == 0:
            continue
        angle = np.degrees(np.arctan2(yy + y0 - y, xx + x0 - x)) % 360
        if len(set(((angle + 22.5) // 45).astype(int) % 8)) == 8:
            return r
    return None


def main():
    s0 = float(sys.argv[2])
    for path in sorted(glob.glob(os.path.join(sys.argv[1], "view*.bin"))):
        d = load(path)
        lab, vis, td = d["lab"].astype(int), d["vis"], d["td"]
        depth = -d["fp"][..., 2]
        h, w = lab.shape
        points = (lab == 1) | (lab == 2)
        fp = (lab == 1) & (vis == 0)
        fn = (lab == 2) & (vis == 1)
        ys, xs = np.nonzero(fp)
        behind = np.array([(depth[y, x] - td[y, x]) / td[y, x] for y, x in zip(ys, xs)])
        radii = [closing_radius(lab, depth, y, x) for y, x in zip(ys, xs)]
        enclosed = sum(r is not None for r in radii)
        print("%s: false positives %d, behind the truth by %.1f / %.1f / %.1f %% of the depth "
              "(10 / 50 / 90 %%), %d enclosed by nearer points within 11 px"
              % (os.path.basename(path), fp.sum(), *(100 * np.percentile(behind, [10, 50, 90])),
                 enclosed))
        near3 = near8 = 0
        for y, x in zip(*np.nonzero(fn)):
            z = depth[y, x]
            for r in (3, 8):
                y0, y1, x0, x1 = max(0, y - r), min(h, y + r + 1), max(0, x - r), min(w, x + r + 1)
                if (points[y0:y1, x0:x1] & (depth[y0:y1, x0:x1] < z - 3 * s0)).any():
                    near3 += r == 3
                    near8 += r == 8
                    break
        to_background = ndimage.distance_transform_edt(lab != 0)[fn]
        print("  false negatives %d: a point nearer by 3 s0 within 3 px %d, within 8 px %d; "
              "within 4 px of the background %d" % (fn.sum(), near3, near8,
                                                     (to_background <= 4).sum()))


if __name__ == "__main__":
    main()
