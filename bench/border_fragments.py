#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# Fill far from the data (issue 15, twentieth round): the pixels of a picture that are not
# black but lie more than 8 px from any pixel that is not black in the raw points' picture
# of the same view, e.g. fragments of fill floating between a silhouette and the image
# border. Both PNGs from strata-view --headless ... --out (--pipeline raw for the first).
# usage: /usr/bin/python3 bench/border_fragments.py RAW.png PICTURE.png   (numpy, scipy, PIL)
import sys

import numpy as np
from PIL import Image
from scipy import ndimage


def main():
    raw = np.asarray(Image.open(sys.argv[1]).convert("RGB")).max(-1) > 0
    picture = np.asarray(Image.open(sys.argv[2]).convert("RGB")).max(-1) > 0
    far = ndimage.distance_transform_edt(~raw) > 8
    print("filled pixels more than 8 px from any point: %d (of %d filled)"
          % ((picture & far).sum(), picture.sum()))


if __name__ == "__main__":
    main()
