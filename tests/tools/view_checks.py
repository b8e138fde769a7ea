# SPDX-License-Identifier: MIT
# What the headless strata-view checks share (check_view_survey.py,
# check_view_point_size.py, check_default_camera.py): the programs of a build, a work
# folder removed at exit, a synth scene converted to .strata, and a tally of checks.
import atexit, os, shutil, subprocess, sys, tempfile


class Build:
    def __init__(self, build_dir):
        self.synth = os.path.join(build_dir, "src", "strata-synth")
        self.convert = os.path.join(build_dir, "preprocess", "strata-convert")
        self.view = os.path.join(build_dir, "src", "strata-view")
        self.work = tempfile.mkdtemp()
        atexit.register(shutil.rmtree, self.work, True)

    def scene(self, kind, points, seed=1, name=None):
        """strata-synth KIND --points POINTS --seed SEED, converted; the .strata path."""
        name = name or kind
        las, scene = (os.path.join(self.work, name + ext) for ext in (".las", ".strata"))
        subprocess.run([self.synth, kind, "--points", str(points), "--seed", str(seed), "-o",
                        las], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        subprocess.run([self.convert, "-q", las, "-o", scene], check=True)
        return scene


class Checks:
    """Prints each check as ok / FAIL; exit() fails the script if any failed."""

    def __init__(self):
        self.failures = []

    def __call__(self, ok, what):
        print(("ok: " if ok else "FAIL: ") + what)
        if not ok:
            self.failures.append(what)

    def exit(self):
        sys.exit(1 if self.failures else 0)
