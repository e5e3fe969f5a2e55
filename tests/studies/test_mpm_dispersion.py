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


class BSplineTest(unittest.TestCase):
    def test_basis_is_a_linear_partition_of_unity(self):
        for degree in (2, 3):
            for a in (0.0, 0.3, 0.5, 0.9):
                rows = [(j, dispersion.cardinal_bspline(a - j, degree))
                        for j in range(-3, 5)]
                self.assertAlmostEqual(sum(v for _, (v, _) in rows), 1.0,
                                       places=14)
                self.assertAlmostEqual(sum(d for _, (_, d) in rows), 0.0,
                                       places=14)
                self.assertAlmostEqual(sum(j * v for j, (v, _) in rows), a,
                                       places=14)

    def test_consistent_mass_symbol(self):
        # int N N(x - j) is the B-spline of degree 2p + 1 at j: at theta = pi
        # (11 - 26/3 + 1/6)/20 = 2/15 (quadratic), (2416 - 2382 + 240 - 2)
        # /5040 = 17/315 (cubic); 1 at theta = 0.
        for degree, at_pi in ((2, 2 / 15), (3, 17 / 315)):
            self.assertAlmostEqual(
                dispersion.bspline_mass_symbol(0.0, degree).real, 1.0,
                places=13)
            self.assertAlmostEqual(
                dispersion.bspline_mass_symbol(math.pi, degree).real, at_pi,
                places=13)

    def test_smooth_basis_leaves_only_the_time_error(self):
        # With the exact mass integral the B-splines' spatial frequency error
        # is of higher order: what remains at second order is leapfrog's
        # +nu^2 theta^2/24 (linear elements: (1 + nu^2)/24, 7x more).
        theta, nu = 0.05, 0.4
        for shape, ppc, tolerance in (("b3spline", 4, 0.005),
                                      ("b2spline", 24, 0.02)):
            error, energy = dispersion.mode_frequency(
                theta, nu, ppc=ppc, shape=shape, update="fmpm",
                mass="consistent", strain="usavg+")
            self.assertAlmostEqual(error / theta ** 2 / (nu ** 2 / 24), 1.0,
                                   delta=tolerance)
            self.assertAlmostEqual(energy, 1.0, places=6)

    def test_bsplines_are_more_stable_than_linear(self):
        # Interior (periodic) limits of the exact full mass: 0.5 linear,
        # higher for the smoother bases (doc/studies/bsplines.md).
        scheme = dict(update="fmpm", mass="full", strain="usavg+")
        linear = dispersion.critical_courant("1d", 2, **scheme)
        quadratic = dispersion.critical_courant("1d", 3, shape="b2spline",
                                                **scheme)
        cubic = dispersion.critical_courant("1d", 4, shape="b3spline",
                                            **scheme)
        self.assertLess(linear + 0.05, quadratic)
        self.assertLess(quadratic + 0.03, cubic)


if __name__ == "__main__":
    unittest.main()
