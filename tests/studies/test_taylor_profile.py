#!/usr/bin/env python3
"""Tests of contrib/utilities/taylor_profile.py.

A quarter rod of radius 3.2 mm filled with the 0.2 mm lattice of points
whose centres lie inside it, as fmpm fills a body: over all points the
foot radius (largest radius plus half a spacing) reads 3.29 mm, over the
points of the rows next to the symmetry planes 3.20 mm, as an
axisymmetric run's points give. The plane rows are chosen by id in the
initial file: after a radial stretch by 2 (points shuffled) they still
give 2 x 3.1016 + 0.1 mm.
"""

import csv
import math
import random
import re
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "contrib" / "utilities" / "taylor_profile.py"
H = 2e-4


def rod(radius=3.2e-3, rows=3):
    points = []
    n = int(radius / H) + 1
    for j in range(rows):
        for i in range(n):
            for k in range(n):
                x, z = (i + 0.5) * H, (k + 0.5) * H
                if math.hypot(x, z) < radius:
                    points.append((len(points), x, (j + 0.5) * H, z))
    return points


def write(path, points):
    with open(path, "w", newline="") as f:
        out = csv.writer(f)
        out.writerow(["id", "body", "material", "x", "y", "z"])
        for p, x, y, z in points:
            out.writerow([p, 0, 0, repr(x), repr(y), repr(z)])


def foot(*args):
    text = subprocess.run([sys.executable, str(SCRIPT), *map(str, args)],
                          check=True, capture_output=True, text=True).stdout
    return float(re.search(r"foot radius ([0-9.]+) mm", text).group(1))


class TaylorProfileTest(unittest.TestCase):
    def test_plane_rows_measure_as_the_axisymmetric_points(self):
        with tempfile.TemporaryDirectory() as tmp:
            initial, stretched = Path(tmp) / "t0.csv", Path(tmp) / "t1.csv"
            points = rod()
            write(initial, points)
            self.assertGreater(foot(initial), 3.28)
            self.assertAlmostEqual(foot(initial, "--plane-rows", initial),
                                   3.202, places=3)
            moved = [(p, 2 * x, y, 2 * z) for p, x, y, z in points]
            random.Random(1).shuffle(moved)
            write(stretched, moved)
            self.assertAlmostEqual(
                foot(stretched, "--plane-rows", initial),
                2 * math.hypot(3.1e-3, 0.1e-3) * 1e3 + 0.1, places=3)

    def test_plane_rows_refuse_axisymmetric_runs(self):
        with tempfile.TemporaryDirectory() as tmp:
            initial = Path(tmp) / "t0.csv"
            write(initial, rod(rows=1))
            result = subprocess.run(
                [sys.executable, str(SCRIPT), str(initial), "--axisymmetric",
                 "--plane-rows", str(initial)], capture_output=True, text=True)
            self.assertNotEqual(result.returncode, 0)
            self.assertIn("--plane-rows is for 3D runs", result.stderr)


if __name__ == "__main__":
    unittest.main()
