#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Would leaf clusters hide what lies behind their unsampled sides if each drawn leaf point
# occluded a screen square of a world radius R (a splat footprint for the occlusion test
# only)? Issue 15, part 2, sixteenth round, second part: measured on the per-pixel dumps of
# bench/patches/issue15_pixel_dump.patch before any shader code. The dump carries no LAS
# class, so the leaf points are taken from the truth (drawn points at pixels whose first hit
# is foliage, no more than BEHIND_M behind it): an upper bound on what a class-based rule
# knows. A point labelled visible is hidden when the dilated leaf depth at its pixel is
# nearer than its own by the gap (metres and relative). Prints per view and setting F1
# before -> after, false positives caught and true visible points wrongly hidden, by the
# truth's material at the pixel.
# usage: /usr/bin/python3 bench/hpr_foliage_footprint.py DUMP_DIR R,GAP_M,GAP_REL ...   (numpy)
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from screen_classes import MATERIALS, load  # noqa: E402

BEHIND_M = 3.0
FRONT_M = 0.3
RADII_PX = (1, 2, 4, 8, 16, 32)
SHOWN = ("road", "wall", "interior", "foliage", "car")


def focal_px(d, point):
    # The dump has no camera: fit x_px = f X / Z + c over the drawn points' positions.
    ys, xs = np.nonzero(point)
    p = d["fp"][ys, xs]
    a = np.stack([p[:, 0] / p[:, 2], np.ones(len(xs))], 1)
    return abs(np.linalg.lstsq(a, xs + 0.5, rcond=None)[0][0])


def min_square(a, r):
    h, w = a.shape
    p = np.pad(a, r, constant_values=np.inf)
    rows = np.full((h + 2 * r, w), np.inf, np.float32)
    for s in range(2 * r + 1):
        rows = np.minimum(rows, p[:, s:s + w])
    out = np.full((h, w), np.inf, np.float32)
    for s in range(2 * r + 1):
        out = np.minimum(out, rows[s:s + h, :])
    return out


def by_material(mask, mat):
    return " ".join(f"{m} {int((mask & (mat == MATERIALS.index(m))).sum())}" for m in SHOWN)


def main():
    for path in sorted(glob.glob(os.path.join(sys.argv[1], "view*.bin"))):
        d = load(path)
        vis, mat = d["vis"], d["mat"]
        point = vis >= 0
        if not point.any():
            continue
        label = d["lab"].round().astype(int)
        z = np.where(point, -d["fp"][..., 2], np.inf).astype(np.float32)
        behind = z - d["td"]
        leaf = point & (mat == MATERIALS.index("foliage")) & (behind < BEHIND_M) & (behind > -FRONT_M)
        f = focal_px(d, point)
        cand = point & (label == 1)
        tp, fp = int((cand & (vis == 1)).sum()), int((cand & (vis == 0)).sum())
        fn = int((point & (label != 1) & (vis == 1)).sum())
        print(f"{os.path.basename(path)}: F1 {2 * tp / (2 * tp + fp + fn):.4f}, focal {f:.1f} px, "
              f"leaf points {int(leaf.sum())}")
        for arg in sys.argv[2:]:
            radius_m, gap_m, gap_rel = (float(v) for v in arg.split(","))
            r_px = np.where(leaf, f * radius_m / np.where(leaf, z, 1.0), 0.0)
            near = np.full(z.shape, np.inf, np.float32)
            for i, r in enumerate(RADII_PX):  # each leaf point in the largest square it fills
                upper = RADII_PX[i + 1] if i + 1 < len(RADII_PX) else np.inf
                sel = leaf & (r_px >= r) & (r_px < upper)
                if sel.any():
                    near = np.minimum(near, min_square(np.where(sel, z, np.inf).astype(np.float32), r))
            hide = cand & (z > np.maximum(near + gap_m, near * (1.0 + gap_rel)))
            caught, wrong = hide & (vis == 0), hide & (vis == 1)
            c, w = int(caught.sum()), int(wrong.sum())
            f1 = 2 * (tp - w) / (2 * (tp - w) + fp - c + fn + w)
            print(f"  R {radius_m} m, gap {gap_m} m / {gap_rel}: F1 {f1:.4f}, caught {c} "
                  f"({by_material(caught, mat)}), wrongly hidden {w} ({by_material(wrong, mat)})")


if __name__ == "__main__":
    main()
