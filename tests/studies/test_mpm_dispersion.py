#!/usr/bin/env python3
"""Tests of contrib/studies/mpm_dispersion.py (the linearised fmpm step).

The textbook dispersion relations, the particle mass matrix of two points
per cell (a = 9/8) and the frequency errors measured in
doc/studies/vibrating_bar.md. Needs numpy (Debian: python3-numpy).
"""

import importlib.util
import math
import sys
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PATH = ROOT / "contrib" / "studies" / "mpm_dispersion.py"
spec = importlib.util.spec_from_file_location("mpm_dispersion", PATH)
dispersion = importlib.util.module_from_spec(spec)
sys.modules["mpm_dispersion"] = dispersion
spec.loader.exec_module(dispersion)

A = 9 / 8  # S^T M S of 2 points per cell = (1 - A) lumped + A consistent


class TextbookTest(unittest.TestCase):
    def test_critical_courant_numbers(self):
        self.assertAlmostEqual(dispersion.fe_critical_courant("lumped"), 1.0,
                               places=6)
        self.assertAlmostEqual(dispersion.fe_critical_courant("consistent"),
                               1 / math.sqrt(3), places=6)
        self.assertAlmostEqual(dispersion.fe_critical_courant("fmpm", 2),
                               math.sqrt(0.6), places=3)  # 0.775
        self.assertAlmostEqual(dispersion.fe_critical_courant("fmpm", 5),
                               0.6196, places=3)

    def test_frequency_errors(self):
        theta, nu = 0.05, 0.4
        for mass in ("lumped", "consistent"):
            exact = dispersion.fe_frequency_error(theta, nu, mass)
            leading = dispersion.fe_frequency_error_leading(theta, nu, mass)
            self.assertAlmostEqual(exact / leading, 1.0, places=2)


class FmpmStepTest(unittest.TestCase):
    def test_particle_mass_matrix_is_nine_eighths_consistent(self):
        cell = dispersion.Cell(math.pi, "1d", ppc=2)
        # Ratio to the lumped mass at theta = pi: 1 - 2a/3 = 1/4.
        self.assertAlmostEqual(cell.full[0, 0].real / cell.lumped[0], 0.25)

    def test_full_mass_limit_and_strip_modes(self):
        scheme = dict(update="fmpm", mass="full", strain="usavg+")
        self.assertAlmostEqual(dispersion.critical_courant("1d", **scheme),
                               0.5, delta=0.01)
        self.assertAlmostEqual(dispersion.critical_courant("strip", **scheme),
                               0.408, delta=0.01)

    def test_mode_frequency_matches_the_leading_terms(self):
        theta, nu = 0.02, 0.4
        flip, flip_energy = dispersion.mode_frequency(
            theta, nu, update="flip", mass="lumped", strain="usavg+")
        self.assertAlmostEqual(flip / theta ** 2,
                               -(1 + 2 * A - nu ** 2) / 24, places=3)
        self.assertAlmostEqual(flip_energy, 1.0, places=9)
        full, _ = dispersion.mode_frequency(theta, nu, update="fmpm",
                                            mass="full", strain="usavg+")
        self.assertAlmostEqual(full / theta ** 2,
                               (2 * A - 1 + nu ** 2) / 24, places=3)
        xpic, _ = dispersion.mode_frequency(theta, nu, update="xpic",
                                            mass="fmpm", order=2,
                                            strain="usavg+")
        self.assertAlmostEqual(xpic / theta ** 2, -(1 - nu ** 2) / 24,
                               places=3)

    def test_pic_damping(self):
        # Energy left after two periods on the bar with 48 cells (theta =
        # pi/64), as measured: 0.748.
        _, factor = dispersion.mode_frequency(
            math.pi / 64, 0.4, update="pic", mass="lumped", strain="usavg+")
        self.assertAlmostEqual(factor ** 2, 0.7488, places=3)


if __name__ == "__main__":
    unittest.main()
