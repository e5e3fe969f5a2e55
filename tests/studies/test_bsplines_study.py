#!/usr/bin/env python3
"""Tests of contrib/studies/bsplines/bsplines.py without fmpm.

The body mesh of the Gauss placement has one cell per knot span of the
open-knot basis inside the bar (so that p + 1 Gauss points a cell
integrate SᵀMS exactly), the planned runs are unique, the fitted order of
a power law is its exponent, and the parameter text nests subsections.
"""

import importlib.util
import math
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PATH = ROOT / "contrib" / "studies" / "bsplines" / "bsplines.py"
spec = importlib.util.spec_from_file_location("bsplines", PATH)
study = importlib.util.module_from_spec(spec)
sys.modules["bsplines"] = study
spec.loader.exec_module(study)


class KnotSpanTest(unittest.TestCase):
    def test_quadratic_spans_are_shifted_by_half_a_cell(self):
        scene = study.Scene("tielen")
        xs = study.knots_in_bar(scene, 8, 2)
        h = scene.h(8)
        # Open knots clamp at 0 and L: 0, h/2, 3h/2, ..., L - h/2, L.
        expected = [0.0] + [(i + 0.5) * h for i in range(8)] + [25.0]
        self.assertEqual(len(xs), len(expected))
        for x, e in zip(xs, expected):
            self.assertAlmostEqual(x, e, places=12)

    def test_free_end_inside_the_mesh_ends_a_piece(self):
        # Vibrating bar: L = 1 inside the mesh [0, 1.5]; for p = 2 the end
        # x = 1 lies in the middle of a knot span, which is cut there.
        scene = study.Scene("vbar")
        for degree in (1, 2, 3):
            xs = study.knots_in_bar(scene, 16, degree)
            self.assertAlmostEqual(xs[0], 0.0)
            self.assertAlmostEqual(xs[-1], 1.0)
            self.assertTrue(all(b > a for a, b in zip(xs, xs[1:])))
            self.assertLessEqual(max(b - a for a, b in zip(xs, xs[1:])),
                                 scene.h(16) * (1 + 1e-12))
        self.assertEqual(len(study.knots_in_bar(scene, 16, 1)), 17)
        self.assertEqual(len(study.knots_in_bar(scene, 16, 2)), 18)

    def test_body_mesh_cells_tile_the_bar(self):
        scene = study.Scene("vbar")
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "bar.inp"
            study.write_body_mesh(path, scene, 8, 2)
            lines = path.read_text().splitlines()
            n_vertices, n_cells = map(int, lines[0].split()[:2])
            xs = study.knots_in_bar(scene, 8, 2)
            self.assertEqual(n_vertices, 2 * len(xs))
            self.assertEqual(n_cells, len(xs) - 1)
            coords = {int(l.split()[0]): tuple(map(float, l.split()[1:3]))
                      for l in lines[1:1 + n_vertices]}
            area = 0.0
            for line in lines[1 + n_vertices:]:
                ids = list(map(int, line.split()[3:]))
                x0, y0 = coords[ids[0]]
                x1, _ = coords[ids[1]]
                _, y2 = coords[ids[2]]
                self.assertGreater(x1, x0)  # counterclockwise
                self.assertGreater(y2, y0)
                area += (x1 - x0) * (y2 - y0)
            self.assertAlmostEqual(area, scene.length * scene.h(8), places=12)


class PlanTest(unittest.TestCase):
    def test_runs_are_unique_and_ugimp_has_no_gauss_points(self):
        plan = study.planned_runs({1, 2, 3, 4, 5, 6, 7})
        keys = [p[1:] for p in plan]
        self.assertEqual(len(keys), len(set(keys)))
        self.assertFalse(any(p[2] == "ugimp" and p[3] == "gauss"
                             for p in plan))

    def test_tiny_step_is_courant_002_at_64_cells(self):
        for name in ("vbar", "tielen"):
            scene = study.Scene(name)
            dt = study.tiny_time_step(scene)
            self.assertAlmostEqual(dt * scene.wave_speed / scene.h(64), 0.02)


class OrderTest(unittest.TestCase):
    def test_power_law(self):
        points = [(n, 3.0 * n ** -3.0) for n in (8, 16, 32, 64)]
        self.assertAlmostEqual(study.fitted_order(points), 3.0, places=12)
        self.assertTrue(math.isnan(study.fitted_order([(8, 1.0)])))

    def test_override_text_nests_subsections(self):
        text = study.override_text([("Mass matrix/Full", "Tolerance",
                                     "1e-13")])
        self.assertEqual(text, "subsection Mass matrix\nsubsection Full\n"
                         "  set Tolerance = 1e-13\nend\nend\n")


if __name__ == "__main__":
    unittest.main()
