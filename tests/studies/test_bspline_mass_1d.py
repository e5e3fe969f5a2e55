#!/usr/bin/env python3
"""Tests of contrib/studies/bspline_mass_1d/bspline_mass_1d.py.

The basis (partition of unity, linear completeness, 1 on the walls), the
reduced step (c, d, w, q, r) against the step of the full point state
(V_p, s_p, u_p) written out directly, the lumped FLIP frequency error of
linear elements against the textbook value, and the orders of the
consistent mass with points on Gauss points (2p). Needs numpy (Debian:
python3-numpy). About 2 s.
"""

import importlib.util
import math
import sys
import unittest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PATH = ROOT / "contrib" / "studies" / "bspline_mass_1d" / "bspline_mass_1d.py"
spec = importlib.util.spec_from_file_location("bspline_mass_1d", PATH)
study = importlib.util.module_from_spec(spec)
sys.modules["bspline_mass_1d"] = study
spec.loader.exec_module(study)
np = study.np


class BasisTest(unittest.TestCase):
    def test_partition_of_unity_and_linear_completeness(self):
        for p in (1, 2, 3):
            n = 7
            for t in np.linspace(0, n, 701):
                S, dS = study.vertex_values(t, p, n)
                i = np.arange(n + 1)
                self.assertAlmostEqual(S.sum(), 1, places=13)
                self.assertAlmostEqual(S @ i, t, places=12)
                self.assertAlmostEqual(dS.sum(), 0, places=12)
                self.assertAlmostEqual(dS @ i, 1, places=12)
                self.assertGreaterEqual(S.min(), -1e-15)
            for wall, vertex in ((0.0, 0), (float(n), n)):
                S, _ = study.vertex_values(wall, p, n)
                self.assertAlmostEqual(S[vertex], 1, places=14)

    def test_gauss_points_integrate_the_mass_exactly(self):
        # Sum of S_i S_j w over the points = exact integral (a fine
        # midpoint sum), p + 1 Gauss points on each knot span.
        for p in (2, 3):
            n = 6
            t, w = study.points(p, n, "gauss")
            S = np.array([study.vertex_values(s, p, n)[0] for s in t])
            mass = S.T @ (w[:, None] * S)
            fine = (np.arange(60000) + 0.5) * n / 60000
            Sf = np.array([study.vertex_values(s, p, n)[0] for s in fine])
            exact = Sf.T @ Sf * (n / 60000)
            self.assertLess(np.abs(mass - exact).max(), 1e-8)


class StepTest(unittest.TestCase):
    def direct(self, p, n, placement, method, k, steps):
        """The step on the full point state, written out."""
        x, volume, S, G = study.operators(p, n, placement)
        mass = study.RHO * volume
        Minv = study.inverse_mass(method, k, S, mass)
        V = np.sin(math.pi * x / study.LENGTH)
        V0 = V.copy()
        stress = np.zeros_like(V)
        u = np.zeros_like(V)
        dt = study.PERIOD / steps
        for _ in range(steps):
            p_grid = S.T @ (mass * V)
            f = -G.T @ (volume * stress)
            v_plus = Minv @ (p_grid + dt * f)
            if method in ("lumped", "consistent", "flip series"):
                V_new = V + dt * (S @ (Minv @ f))
                u = u + dt * (S @ v_plus)
            else:
                V_new = S @ v_plus
                u = u + 0.5 * dt * (V + V_new)
            V = V_new
            stress = stress + dt * study.E * (G @ v_plus)
        error = math.sqrt(
            np.sum(volume * ((study.OMEGA * u) ** 2 + (V - V0) ** 2)) /
            np.sum(volume * V0 ** 2))
        return error

    def test_reduced_step_equals_the_full_point_state(self):
        for p, placement, method, k in ((2, "gauss", "lumped", 0),
                                        (3, "uniform", "consistent", 0),
                                        (2, "uniform", "fmpm", 3),
                                        (2, "gauss", "flip series", 4),
                                        (1, "gauss", "fmpm exact", 0)):
            reduced = study.error_after_one_period(p, 6, placement, method,
                                                   k, 300)
            direct = self.direct(p, 6, placement, method, k, 300)
            self.assertAlmostEqual(reduced / direct, 1, places=9,
                                   msg=f"{p} {placement} {method} {k}")

    def test_lumped_flip_frequency_error_of_linear_elements(self):
        # FLIP with the lumped mass and frozen points moves the grid with
        # the mass m (S^T M S)^-1 m: omega_h = omega (1 - theta^2/8) to
        # leading order (lumped FE -theta^2/24, times the mass ratio
        # (2 + cos theta)/3 = 1 - theta^2/6 under the root: -theta^2/12),
        # theta = pi h / L; one period's phase error 2 pi theta^2 / 8.
        n = 64
        theta = math.pi / n
        error = study.error_after_one_period(1, n, "gauss", "lumped", 0,
                                             2 ** 16)
        self.assertAlmostEqual(error / (2 * math.pi * theta ** 2 / 8), 1,
                               places=2)

    def test_consistent_mass_orders_on_gauss_points(self):
        for p, expected in ((1, 2), (2, 4), (3, 6)):
            e = [study.error_after_one_period(p, n, "gauss", "consistent",
                                              0, 2 ** 23) for n in (8, 16)]
            self.assertAlmostEqual(math.log2(e[0] / e[1]), expected,
                                   delta=0.15, msg=f"p = {p}")

    def test_series_does_not_reach_the_full_mass_at_tiny_steps(self):
        # doc/studies/bspline_mass_1d.md: FMPM(16) stays far above
        # FMPM(exact) at 16 cells, and FLIP with the series above FLIP with
        # the consistent mass, while at 8 cells the FLIP series has
        # converged; the series' own partial sums converge to m~^-1.
        steps = 2 ** 23
        ratio = [study.error_after_one_period(2, 16, "gauss", a, k, steps) /
                 study.error_after_one_period(2, 16, "gauss", b, 0, steps)
                 for a, b, k in (("fmpm", "fmpm exact", 16),
                                 ("flip series", "consistent", 16))]
        self.assertGreater(ratio[0], 20)
        self.assertGreater(ratio[1], 3)
        converged = (
            study.error_after_one_period(2, 8, "gauss", "flip series", 16,
                                         steps) /
            study.error_after_one_period(2, 8, "gauss", "consistent", 0,
                                         steps))
        self.assertAlmostEqual(converged, 1, delta=0.05)
        x, volume, S, G = study.operators(2, 8, "gauss")
        mass = study.RHO * volume
        self.assertLess(
            np.abs(study.inverse_mass("flip series", 400, S, mass) -
                   study.inverse_mass("consistent", 0, S, mass)).max(),
            1e-8)


if __name__ == "__main__":
    unittest.main()
