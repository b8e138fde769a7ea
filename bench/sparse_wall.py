#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Black pixels of shaded renders (issue 15, part 2, sixteenth round: sparse surfaces
# under the per-pixel gaps): per PNG the pure-black pixels in the whole picture and in
# a crop given as fractions of the picture (default: the README view's near beige wall,
# x 350-549, y 40-239 at 1920x1080), and, against the first PNG of the same size, the
# pixels that turned black and those that were filled.
# usage: /usr/bin/python3 bench/sparse_wall.py A.png B.png ...   (numpy, PIL)
#   (CROP=x0,y0,x1,y1 as fractions of the width and height)
import os
import sys

import numpy as np
from PIL import Image

CROP = [float(v) for v in os.environ.get("CROP", "0.18229,0.03704,0.28646,0.22222").split(",")]


def black(path):
    rgb = np.asarray(Image.open(path).convert("RGB"), dtype=np.uint16)
    return rgb.sum(axis=2) == 0


first = {}
for path in sys.argv[1:]:
    b = black(path)
    h, w = b.shape
    x0, y0, x1, y1 = (int(round(f * s)) for f, s in zip(CROP, (w, h, w, h)))
    line = "%s %dx%d: black %d, in the crop x %d-%d y %d-%d %d" % (
        os.path.basename(path), w, h, b.sum(), x0, x1 - 1, y0, y1 - 1, b[y0:y1, x0:x1].sum())
    ref = first.setdefault((w, h), b)
    if ref is not b:
        line += "; against the first: turned black %d, filled %d" % ((b & ~ref).sum(),
                                                                         (ref & ~b).sum())
    print(line)
