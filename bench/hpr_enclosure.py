#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# What an "enclosed" rule would do to HPR's labels on the street views (issue 15, part 2,
# sixteenth round, second part), measured on the per-pixel dumps of
# bench/patches/issue15_pixel_dump.patch before any shader code: a point labelled visible
# is hidden when, in every one of 8 screen directions (or NEED of them), the nearest depth
# of a min-depth pyramid at level L, within K cells of the point's cell, is nearer than
# its own depth by the relative gap G (and by the absolute gap A metres). MODE points
# builds the pyramid from the drawn points' depths, MODE filled from the fill's depth (the
# pull-push filled surface, holes included). With a sixth field PAIRS the point is hidden
# instead when PAIRS of the 4 opposite direction pairs are both closed. Drawn points within 0.15 m of the truth's
# window glass stand in for the see-through returns (the dump has no see-through mark)
# and are left out of the pyramid. Prints per view F1 before -> after, the false
# positives caught and the true visible points wrongly hidden, by the truth's material
# at the pixel, and the screen footprint of the cars and leaf clusters: how many truly
# visible drawn points lie in them.
# With PNG_DIR set it also writes enclosureN.png: the drawn points' depth (log colour scale,
# false positives white) above the truth's first-hit depth (cars tinted red).
# usage: /usr/bin/python3 bench/hpr_enclosure.py DUMP_DIR points|filled L,K,A,G,NEED[,PAIRS][+...] ...
#   (a setting joined with + hides a point when any of its parts does; numpy, PIL for PNG_DIR)
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from screen_classes import MATERIALS, load  # noqa: E402

DIRECTIONS = ((1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1))
GLASS_TOLERANCE_M = 0.15
PYRAMID_LEVELS = 7
SHOWN = ("road", "wall", "interior", "pole", "foliage", "car")


def min_pyramid(depth):
    levels = [depth]
    for _ in range(PYRAMID_LEVELS):
        a = levels[-1]
        h, w = a.shape
        b = np.full(((h + 1) // 2 * 2, (w + 1) // 2 * 2), np.inf, np.float32)
        b[:h, :w] = a
        levels.append(b.reshape(b.shape[0] // 2, 2, b.shape[1] // 2, 2).min(axis=(1, 3)))
    return levels


def enclosed(pyramid, xs, ys, z, setting):
    level, reach, gap_m, gap_rel, need = setting[:5]
    pairs = setting[5] if len(setting) > 5 else 0
    a = pyramid[level]
    h, w = a.shape
    cx, cy = xs >> level, ys >> level
    threshold = np.minimum(z - gap_m, z * (1.0 - gap_rel))
    closed = {}
    for dx, dy in DIRECTIONS:
        nearest = np.full(len(z), np.inf, np.float32)
        for step in range(1, reach + 1):
            x, y = cx + dx * step, cy + dy * step
            inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
            v = np.full(len(z), np.inf, np.float32)
            v[inside] = a[y[inside], x[inside]]
            nearest = np.minimum(nearest, v)
        closed[(dx, dy)] = nearest < threshold
    if pairs > 0:  # a point between two nearer samples on a line (thin occluders)
        both = sum((closed[(dx, dy)] & closed[(-dx, -dy)]).astype(int) for dx, dy in DIRECTIONS[:4])
        return both >= pairs
    return sum(c.astype(int) for c in closed.values()) >= need


def log_colour(z, mask):
    t = np.clip(np.log(np.clip(np.where(mask, z, 1.0), 1.0, 200.0)) / np.log(200.0), 0.0, 1.0)
    img = np.stack([255 * t, 255 * (1 - np.abs(2 * t - 1)), 255 * (1 - t)], -1).astype(np.uint8)
    img[~mask] = 0
    return img


def write_png(d, point, depth, label, name):
    from PIL import Image
    drawn = log_colour(depth, point)
    drawn[point & (label == 1) & (d["vis"] == 0)] = (255, 255, 255)
    truth = log_colour(d["td"], np.isfinite(d["td"]) & (d["td"] > 0))
    car = d["mat"] == MATERIALS.index("car")
    truth[car] = truth[car] // 2 + np.array([128, 0, 0], np.uint8)
    out = os.path.join(os.environ["PNG_DIR"], "enclosure" + name[4:-4] + ".png")
    Image.fromarray(np.concatenate([drawn[::-1], truth[::-1]], 0)).save(out)


def by_material(mask, mat):
    return " ".join(f"{m} {int((mask & (mat == MATERIALS.index(m))).sum())}" for m in SHOWN)


def main():
    dump_dir, mode = sys.argv[1], sys.argv[2]
    settings = [[tuple(int(v) if i in (0, 1, 4, 5) else float(v) for i, v in enumerate(part.split(",")))
                 for part in arg.split("+")] for arg in sys.argv[3:]]
    for path in sorted(glob.glob(os.path.join(dump_dir, "view*.bin"))):
        d = load(path)
        vis, mat = d["vis"], d["mat"]
        point = vis >= 0
        label = d["lab"].round().astype(int)
        surface = point if mode == "points" else d["fp"][..., 3] > 0
        depth = np.where(surface, -d["fp"][..., 2], np.inf).astype(np.float32)
        glass = np.isfinite(d["gd"]) & (np.abs(depth - d["gd"]) < GLASS_TOLERANCE_M)
        pyramid = min_pyramid(np.where(glass, np.inf, depth).astype(np.float32))
        ys, xs = np.nonzero(point & (label == 1))
        z = depth[ys, xs]
        truly = vis[ys, xs] == 1
        tp = int((point & (label == 1) & (vis == 1)).sum())
        fp = int((point & (label == 1) & (vis == 0)).sum())
        fn = int((point & (label != 1) & (vis == 1)).sum())
        name = os.path.basename(path)
        if os.environ.get("PNG_DIR"):
            write_png(d, point, np.where(point, -d["fp"][..., 2], np.inf), label, name)
        print(f"{name}: F1 {2 * tp / (2 * tp + fp + fn):.4f} (tp {tp} fp {fp} fn {fn})")
        for kind in ("car", "foliage"):
            foot = mat == MATERIALS.index(kind)
            print(f"  {kind} footprint {int(foot.sum())} px, truly visible drawn points in it "
                  f"{int((foot & (vis == 1)).sum())}, false positives in it "
                  f"{int((foot & point & (label == 1) & (vis == 0)).sum())}")
        for arg, setting in zip(sys.argv[3:], settings):
            hide = np.zeros(len(z), bool)
            for part in setting:
                hide |= enclosed(pyramid, xs, ys, z, part)
            caught, wrong = int((hide & ~truly).sum()), int((hide & truly).sum())
            tp2, fp2, fn2 = tp - wrong, fp - caught, fn + wrong
            m = mat[ys, xs]
            print(f"  {mode} {arg}: F1 {2 * tp2 / (2 * tp2 + fp2 + fn2):.4f}, caught {caught} "
                  f"({by_material(hide & ~truly, m)}), wrongly hidden {wrong} "
                  f"({by_material(hide & truly, m)})")


if __name__ == "__main__":
    main()
