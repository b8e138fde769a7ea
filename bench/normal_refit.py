#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# A robust plane refit at creases, measured on the pixel dump and left (issue 15,
# twenty-first round, docs/BENCHMARKS.md "two leads measured and left"): for every
# counted pixel, an iteratively reweighted plane fit of the filled level-0 positions in a
# disc of radius R px (weights exp(-(d / h)^2), d the distance to the current plane
# through the pixel's position), started from the pyramid's normal; taken only where it
# turns that normal by more than T degrees. Prints median, p95 and the share off by more
# than 30 degrees over the counted pixels (a truth hit, a normal, a filled position, no
# vegetation) and over those whose filled depth is within TAU_M of the truth.
# usage: /usr/bin/python3 bench/normal_refit.py DUMP_DIR/view0.bin [R=5] [H_M=0.05] [T=15]
#   (the dumps of bench/patches/issue15_pixel_dump.patch, STA_BENCH_DUMP=DIR; numpy;
#   about 2 GB of memory at 960x540 with R = 5)
import sys

import numpy as np

from screen_classes import MATERIALS, load

TAU_M = 0.186  # strata-bench's truth tolerance on street view 0 at 960x540


def angle_deg(a, b):
    c = np.abs(np.sum(a * b, -1)) / np.maximum(
        np.linalg.norm(a, axis=-1) * np.linalg.norm(b, axis=-1), 1e-30)
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


def report(name, normals, truth, counted, right):
    e = angle_deg(normals, truth)
    ec, er = e[counted], e[counted & right]
    print(f"{name}: median {np.median(ec):.2f}, p95 {np.percentile(ec, 95):.1f}, off > 30 deg "
          f"{100 * (ec > 30).mean():.2f} %; right depth: off {100 * (er > 30).mean():.2f} %, "
          f"p95 {np.percentile(er, 95):.1f}")


def main():
    d = load(sys.argv[1])
    radius = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    h = float(sys.argv[3]) if len(sys.argv) > 3 else 0.05
    turn = float(sys.argv[4]) if len(sys.argv) > 4 else 15.0
    td, tn, fp, nm, mat = d["td"], d["tn"], d["fp"], d["nm"][..., :3], d["mat"]
    vegetation = (mat == MATERIALS.index("trunk")) | (mat == MATERIALS.index("foliage"))
    has_normal = np.linalg.norm(nm, axis=-1) > 0
    filled = fp[..., 3] > 0
    counted = np.isfinite(td) & (td > 0) & has_normal & filled & ~vegetation
    right = np.abs(-fp[..., 2] - td) <= TAU_M
    report("pyramid", nm, tn, counted, right)
    height, width = td.shape
    positions = np.where(filled[..., None], fp[..., :3], np.nan)
    padded = np.pad(positions, ((radius, radius), (radius, radius), (0, 0)),
                    constant_values=np.nan)
    offsets = [(dy, dx) for dy in range(-radius, radius + 1) for dx in range(-radius, radius + 1)
               if dx * dx + dy * dy <= radius * radius + 1]
    q = np.stack([padded[radius + dy:radius + dy + height, radius + dx:radius + dx + width]
                  for dy, dx in offsets], axis=2)
    valid = np.isfinite(q[..., 0])
    q = np.nan_to_num(q)
    centre = fp[..., :3]
    n = nm.copy()
    dist = np.sum((q - centre[:, :, None, :]) * n[:, :, None, :], -1)
    w = valid * np.exp(-(dist / h) ** 2)
    sw = np.maximum(w.sum(-1), 1e-12)
    mean = (w[..., None] * q).sum(2) / sw[..., None]
    x = q - mean[:, :, None, :]
    cov = np.einsum('hwk,hwki,hwkj->hwij', w, x, x)
    refit = np.linalg.eigh(cov + np.eye(3) * 1e-12)[1][..., :, 0]
    refit = np.where((np.sum(refit * n, -1) < 0)[..., None], -refit, refit)
    refit = np.where(((sw > 3) & has_normal)[..., None], refit, n)
    report("refit everywhere", refit, tn, counted, right)
    hybrid = np.where((angle_deg(refit, n) > turn)[..., None], refit, n)
    report(f"refit where it turns the normal by more than {turn:g} deg", hybrid, tn, counted,
           right)


if __name__ == "__main__":
    main()
