#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Where the street's wrong normals are (issue 15, part 3, sixteenth round): reads the dumps
# that bench/patches/issue15_pixel_dump.patch makes strata-bench write (STA_BENCH_DUMP=DIR)
# and prints, per view, the share of the counted pixels (a normal, a truth hit, not a
# vegetation material) whose normal is off by more than 30 degrees, split by what the
# fill did there: its depth more than TAU_M off the truth (the fill's share: on sampled
# window glass, nearer or farther than the truth) or right (the estimator's share: on a
# face facing the camera or not, by material); and the pull-push coverage (the filled
# position's w) of the pixels, with the share of wrong normals at each.
# usage: /usr/bin/python3 bench/normal_classes.py DUMP_DIR [TAU_M=0.186]   (numpy)
#   TAU_M: strata-bench's truth tolerance, 3 s0 + 3 noise sigma (0.186 / 0.172 / 0.162 m on
#   the three street views at 960x540; one value for all views here)
import glob
import os
import sys

import numpy as np

from screen_classes import MATERIALS, load

OFF_DEG = 30.0     # STA_VIEW_NORMAL_OFF_DEG
FACING_DEG = 37.0  # STA_VIEW_FACING_ANGLE_DEG
VEGETATION = (MATERIALS.index("trunk"), MATERIALS.index("foliage"))


def angle_deg(a, b):
    la = np.linalg.norm(a, axis=-1)
    lb = np.linalg.norm(b, axis=-1)
    c = np.sum(a * b, -1) / np.maximum(la * lb, 1e-30)
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


def main():
    dump_dir = sys.argv[1]
    tau = float(sys.argv[2]) if len(sys.argv) > 2 else 0.186
    for path in sorted(glob.glob(os.path.join(dump_dir, "view*.bin"))):
        d = load(path)
        td, tn, fp, nm, mat = d["td"], d["tn"], d["fp"], d["nm"], d["mat"]
        hit = np.isfinite(td) & (td > 0)
        counted = hit & (nm[..., 3] > 0.5) & ~np.isin(mat, VEGETATION)
        n = counted.sum()
        err = angle_deg(nm[..., :3], tn)
        off = counted & (err > OFF_DEG)
        depth = -fp[..., 2]
        depth_off = np.abs(depth - td) > tau
        gd = d["gd"]
        on_glass = np.isfinite(gd) & (gd < td - 0.01) & (np.abs(depth - gd) <= tau)
        facing = np.abs(tn[..., 2]) >= np.cos(np.radians(FACING_DEG))

        def pct(mask):
            return 100.0 * mask.sum() / max(n, 1)

        print(f"{os.path.basename(path)}: {n} counted pixels, off > {OFF_DEG:g} deg {pct(off):.2f} %")
        f = off & depth_off
        print(f"  fill off by more than {tau:g} m: {pct(f):.2f} % (on sampled glass {pct(f & on_glass):.2f} %,"
              f" nearer {pct(f & (depth < td) & ~on_glass):.2f} %, farther {pct(f & (depth > td)):.2f} %)")
        r = off & ~depth_off
        for name, m in (("facing the camera", facing), ("other faces", ~facing)):
            counts = np.bincount(mat[r & m], minlength=len(MATERIALS))
            top = ", ".join(f"{MATERIALS[i]} {100.0 * counts[i] / n:.2f}" for i in np.argsort(-counts)[:4]
                            if counts[i])
            print(f"  depth right, {name}: {pct(r & m):.2f} % ({top})")
        w = fp[..., 3]
        for lo, hi in ((0.0, 0.9), (0.9, 0.95), (0.95, 0.99), (0.99, 1.0), (1.0, 2.0)):
            m = counted & (w >= lo) & (w < hi)
            rate = 100.0 * (m & off).sum() / max(m.sum(), 1)
            print(f"  coverage [{lo:g}, {hi:g}): {pct(m):.2f} % of the pixels, {rate:.0f} % of them off")


if __name__ == "__main__":
    main()
