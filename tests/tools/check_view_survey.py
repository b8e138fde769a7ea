#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
# strata-view's surveyor options headless (label gl, EGL llvmpipe): --classes shows only
# the kept classes' colours, --clip leaves the far side black, --pick prints the point
# drawn under the pixel (its class colour is the pixel's), --measure lists values,
# --hud changes only the readout's corner.
# usage: check_view_survey.py BUILD-DIR
import os, subprocess, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_rows import png  # noqa: E402
from view_checks import Build  # noqa: E402

build = Build(sys.argv[1])
view, work = build.view, build.work

def colour(r, g, b):  # shaders/geometry.vert's class colours, 8-bit
    return tuple(int(v * 255 + 0.5) for v in (r, g, b))

GROUND, BUILDING = colour(0.65, 0.50, 0.35), colour(0.85, 0.35, 0.25)

def near(a, b, tol=3):
    return all(abs(x - y) <= tol for x, y in zip(a, b))

scene = build.scene("street", 300000)
cam = "--camera=650235,5401873.6,105.5,180,-8,70"
base = [view, "--headless", scene, cam, "--size", "320x180", "--pipeline", "raw", "--colour", "class"]

def render(name, *extra):
    out = os.path.join(work, name + ".png")
    r = subprocess.run(base + list(extra) + ["--out", out], check=True, capture_output=True, text=True)
    return png(out), r.stdout

(w, h, full), _ = render("full")
(_, _, ground_only), _ = render("ground", "--classes", "2")
drawn = [p for row in ground_only for p in row if p != (0, 0, 0)]
assert len(drawn) > 1000, "--classes 2 drew almost nothing"
assert all(near(p, GROUND) for p in drawn), "--classes 2 drew other colours"
assert any(near(p, BUILDING) for row in full for p in row), "the full view has no building"

# --clip: only x below 650220 (the camera at x 650235 looks along -x): near points go.
(_, _, clipped), _ = render("clip", "--clip", "650100,5401000,0,650220,5402000,200")
bottom = lambda img: sum(p != (0, 0, 0) for row in img[h - 20:] for p in row)
nb_full, nb_clip = bottom(full), bottom(clipped)
assert nb_full > 300 and nb_clip < nb_full // 10, ("--clip kept the near ground", nb_full, nb_clip)

# --pick: the printed class is the one whose colour is drawn at the pixel.
names = {2: GROUND, 6: BUILDING, 5: colour(0.10, 0.50, 0.15), 11: colour(0.35, 0.35, 0.38),
         13: colour(0.95, 0.85, 0.10), 14: colour(0.95, 0.85, 0.10), 15: colour(0.80, 0.55, 0.10)}
for x, y in ((160, 150), (40, 40)):
    _, out = render("pick", "--pick", "%d,%d" % (x, y))
    line = [l for l in out.splitlines() if l.startswith("pick")][0]
    cls = int(line.split("class ")[1].split()[0])
    assert cls in names, line
    window = [full[yy][xx] for yy in range(y - 4, y + 5) for xx in range(x - 4, x + 5)]
    assert any(near(p, names[cls]) for p in window), (line, window[:5])
    coords = line.split(": ")[1].split()
    assert coords[0] == "x" and len(coords[1].split(".")[1]) == 3, line  # the grid's mm

# --measure and --hud: values printed; only the top-left corner changes.
m = os.path.join(work, "m.json")
open(m, "w").write('{"measurements": [{"kind": "distance", "name": "d", "points": '
                   '[[650200, 5401860, 103], [650203, 5401864, 115]]}]}')
(_, _, hud), out = render("hud", "--measure", m, "--hud")
assert "measure 1 d: 3D 13.000 m, horizontal 5.000 m, vertical +12.000 m" in out, out
changed = [(x, y) for y in range(h) for x in range(w) if hud[y][x] != full[y][x]]
corner = [(x, y) for x, y in changed if y < 80]
markers = [(x, y) for x, y in changed if y >= 80]
assert corner, "no readout in the corner"
# Outside the text's corner only the measurement's markers (yellow) are drawn.
assert markers and all(hud[y][x] == (255, 220, 0) for x, y in markers), \
    ("the readout drew outside its corner", markers[:5])
print("view survey options: ok (%d drawn ground pixels, %d readout pixels, %d marker pixels)"
      % (len(drawn), len(corner), len(markers)))
