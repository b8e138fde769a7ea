#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# strata-view's default camera given back (label gl, EGL llvmpipe): with --stats and no
# --camera the viewer prints the default view's --camera option; rendering with that
# option shows the same picture (a synth sphere seen from the south-west, a synth street
# along its axis). Only the near plane differs (a given camera's is set from the scene's
# extent), which moves a few nearest-point picks: at most 0.1 % of the pixels may differ.
# A camera one degree off differs in far more.
# usage: check_default_camera.py BUILD-DIR
import os, re, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_rows import png  # noqa: E402
from view_checks import Build, Checks  # noqa: E402

build = Build(sys.argv[1])
view, work = build.view, build.work
check = Checks()


def render(scene, out, *options):
    r = subprocess.run([view, "--headless", scene, "--size", "320x180", "--out", out, "--stats"]
                       + list(options), check=True, capture_output=True, text=True)
    return r.stdout


def differing(a, b):
    (w, h, rows_a), (_, _, rows_b) = png(a), png(b)
    return sum(1 for ra, rb in zip(rows_a, rows_b) for pa, pb in zip(ra, rb) if pa != pb), w * h


for kind, points in (("sphere", "60000"), ("street", "200000")):
    scene = build.scene(kind, points)
    default = os.path.join(work, kind + "_default.png")
    stats = render(scene, default)
    m = re.search(r"^default camera: (--camera=([-0-9.e]+(,[-0-9.e]+){5}))$", stats, re.M)
    check(m is not None, f"{kind}: the default camera printed as an option")
    if not m:
        continue
    given = os.path.join(work, kind + "_given.png")
    stats_given = render(scene, given, m.group(1))
    check("default camera:" not in stats_given, f"{kind}: no default camera line for a given one")
    diff, total = differing(default, given)
    check(diff <= total // 1000, f"{kind}: {m.group(1)} shows the default view "
          f"({diff} of {total} pixels differ)")
    numbers = [float(v) for v in m.group(2).split(",")]
    numbers[3] += 1.0  # one degree of yaw
    turned = os.path.join(work, kind + "_turned.png")
    render(scene, turned, "--camera=" + ",".join(repr(v) for v in numbers))
    diff, total = differing(default, turned)
    check(diff > total // 100, f"{kind}: a camera one degree off shows another view "
          f"({diff} pixels differ)")
check.exit()
