#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# strata-view's point size headless (label gl, EGL llvmpipe): bad --point-size values
# and a minimum above the maximum are refused naming the option; 3 px points cover
# more of the raw picture than 1 px and the same pixels with both rasterisers; adaptive
# sizes change the raw picture too; the shaded pipeline ignores the size.
# usage: check_view_point_size.py BUILD-DIR
import os, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_rows import png  # noqa: E402
from view_checks import Build, Checks  # noqa: E402

build = Build(sys.argv[1])
view, work = build.view, build.work
scene = build.scene("street", 200000)
cam = "--camera=650235,5401873.6,105.5,180,-8,70"
check = Checks()


for bad, named in (
    (["--point-size", "0.5"], "--point-size"),
    (["--point-size", "huge"], "--point-size"),
    (["--point-size", "65"], "--point-size"),
    (["--point-size-min", "5", "--point-size-max", "2"], "--point-size-min"),
):
    r = subprocess.run([view, "--headless", scene, "--out", os.path.join(work, "x.png")] + bad,
                       capture_output=True, text=True)
    check(r.returncode == 2 and named in r.stderr, f"{' '.join(bad)} refused: {r.stderr.strip()}")


def render(name, *args):
    out = os.path.join(work, name + ".png")
    subprocess.run([view, "--headless", scene, cam, "--size", "240x135", "--out", out] + list(args),
                   check=True, stdout=subprocess.DEVNULL)
    return out


def covered(path):
    _, _, rows = png(path)
    return sum(1 for row in rows for p in row if p != (0, 0, 0))


one = render("one", "--pipeline", "raw")
three = render("three", "--pipeline", "raw", "--point-size", "3")
three_points = render("three_points", "--pipeline", "raw", "--point-size", "3", "--raster", "points")
adaptive = render("adaptive", "--pipeline", "raw", "--point-size", "adaptive", "--point-size-max", "6")
a, b, c = covered(one), covered(three), covered(adaptive)
print(f"non-black pixels: 1 px {a}, 3 px {b}, adaptive 1-6 px {c} of {240 * 135}")
check(b > a * 1.2, "3 px points cover more than 1 px")
check(c > a, "adaptive points cover more than 1 px")
check(png(three) == png(three_points), "3 px: compute and GL_POINTS draw the same picture")
shaded = render("shaded", "--pipeline", "shaded")
shaded3 = render("shaded3", "--pipeline", "shaded", "--point-size", "3")
check(png(shaded) == png(shaded3), "the shaded pipeline ignores --point-size")
check.exit()
