#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Per-pixel error classes of the filled depth and of HPR on the street views (issue 15,
# sixth round): which pixels make up the worst 5 %. Reads the dumps that
# bench/patches/issue15_pixel_dump.patch makes strata-bench write (STA_BENCH_DUMP=DIR)
# and prints, per view: the filled-depth p95 over all pixels, over sampled pixels, with
# window glass accepted as a surface ("glass or behind": the fill is right when it is
# within 5 % of the glass or of the room behind), and both; the pixels off by more than
# 5 % by the material the truth ray hits, the HPR label and the side of the error; HPR's
# false positives / negatives by material. With an output folder it also writes
# classN.png (grey: right; red / orange: sampled, fill too far / too near; teal:
# unsampled and off; olive: right only as glass; navy: a true surface left empty).
# usage: /usr/bin/python3 bench/screen_classes.py DUMP_DIR [PNG_DIR]   (numpy, PIL)
import glob
import os
import sys

import numpy as np

MATERIALS = ("none road marking curb sidewalk wall glass door interior pole wire trunk "
             "foliage car tyre surface").split()
LABELS = {0: "background", 1: "visible", 2: "hidden", 3: "hole"}


def load(path):
    with open(path, "rb") as f:
        w, h = np.frombuffer(f.read(8), np.int32)
        n = int(w) * int(h)

        def take(dtype, per):
            size = np.dtype(dtype).itemsize * per * n
            a = np.frombuffer(f.read(size), dtype)
            return a.reshape((h, w, per) if per > 1 else (h, w))
        return dict(td=take(np.float32, 1), tn=take(np.float32, 3), lab=take(np.float32, 1),
                    fp=take(np.float32, 4), nm=take(np.float32, 4), samp=take(np.uint8, 1),
                    vis=take(np.int8, 1), mat=take(np.uint8, 1), gd=take(np.float32, 1))


def p95(values):
    if len(values) == 0:
        return float("nan")
    s = np.sort(values)
    return s[int(np.ceil(0.95 * len(s))) - 1]  # nearest rank, as strata-bench


def main():
    dump_dir = sys.argv[1]
    png_dir = sys.argv[2] if len(sys.argv) > 2 else None
    for path in sorted(glob.glob(os.path.join(dump_dir, "view*.bin"))):
        d = load(path)
        td, fp, samp, mat = d["td"], d["fp"], d["samp"] == 1, d["mat"]
        hit = np.isfinite(td) & (td > 0)
        safe = np.where(hit, td, 1.0)
        filled = fp[..., 3] > 0
        depth = -fp[..., 2]
        m = hit & filled
        err = np.where(m, np.abs(depth - td) / safe, 0.0)
        gd = np.where(np.isfinite(d["gd"]), d["gd"], safe)
        glass_err = np.where(m, np.abs(depth - gd) / gd, 0.0)
        either = np.minimum(err, glass_err)
        name = os.path.basename(path)
        print(f"{name}: depth p95 all {100 * p95(err[m]):.2f} %, sampled "
              f"{100 * p95(err[m & samp]):.2f} %, glass or behind {100 * p95(either[m]):.2f} %, "
              f"both {100 * p95(either[m & samp]):.2f} %  ({m.sum()} pixels, "
              f"{(hit & ~filled).sum()} true surface left empty)")
        bad = m & (err > 0.05)
        label = d["lab"].round().astype(int)
        print(f"  off by > 5 %: {bad.sum()} ({100 * bad.sum() / max(m.sum(), 1):.1f} %)")
        for k, mname in enumerate(MATERIALS):
            c = bad & (mat == k)
            if c.sum() < 0.001 * m.sum():
                continue
            parts = ", ".join(f"{LABELS[v]} {(c & (label == v)).sum()}" for v in (1, 2, 3))
            print(f"    {mname:9s} {c.sum():7d} ({100 * c.sum() / m.sum():.2f} %): sampled "
                  f"{(c & samp).sum()}, fill too near {(c & (depth < td)).sum()}, right as glass "
                  f"{(c & (glass_err <= 0.05)).sum()}; labels {parts}")
        vis = d["vis"]
        point = vis >= 0
        lv, tv = label == 1, vis == 1
        tp, fpos, fneg = (point & lv & tv).sum(), (point & lv & ~tv).sum(), (point & ~lv & tv).sum()
        print(f"  HPR F1 {2 * tp / max(2 * tp + fpos + fneg, 1):.4f}: tp {tp} fp {fpos} fn {fneg}")
        for k, mname in enumerate(MATERIALS):
            a, b = (point & lv & ~tv & (mat == k)).sum(), (point & ~lv & tv & (mat == k)).sum()
            if a + b >= 0.02 * max(fpos + fneg, 1):
                print(f"    pixel's truth {mname:9s} fp {a:6d} fn {b:6d}")
        if png_dir:
            from PIL import Image
            g = np.where(hit, 60 + 120 * np.exp(-np.where(hit, td, 0) / 30), 0).astype(np.uint8)
            img = np.stack([g, g, g], -1)
            img[hit & ~filled] = (0, 0, 90)
            img[m & ~samp & (err > 0.05)] = (0, 90, 90)
            img[m & (err > 0.05) & (glass_err <= 0.05)] = (90, 90, 0)
            worst = m & samp & (either > 0.05)
            img[worst & (depth > td)] = (255, 0, 0)
            img[worst & (depth <= td)] = (255, 160, 0)
            out = os.path.join(png_dir, "class" + name[4:-4] + ".png")
            Image.fromarray(img[::-1]).save(out)


if __name__ == "__main__":
    main()
