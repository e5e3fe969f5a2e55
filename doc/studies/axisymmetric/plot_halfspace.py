#!/usr/bin/env python3
"""Centre settlement of the circular load on a half-space against time
(halfspace_history.csv: time, track1_uy, kinetic_energy, strain_energy of
parameters/circular_load_halfspace.prm's history.csv) with the exact
quasi-static settlement q s(t) w(a/32)."""
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = os.path.dirname(os.path.abspath(__file__))
q, a, E, nu, t0, d = 1e4, 1.0, 1e7, 0.3, 2.0, 1.0 / 32
s = math.sqrt(a * a + d * d)
w_exact = q * (1 + nu) / E * (2 * (1 - nu) * (s - d) + d * (1 - d / s))
with open(os.path.join(here, "halfspace_history.csv"), newline="") as f:
    rows = list(csv.DictReader(f))
t = [float(r["time"]) for r in rows]
w = [-1e3 * float(r["track1_uy"]) for r in rows]
ramp = [(1 - math.cos(math.pi * x / t0)) / 2 if x < t0 else 1.0 for x in t]
fig, ax = plt.subplots(figsize=(5.5, 3.6))
ax.plot(t, w, label="fmpm, axisymmetric")
ax.plot(t, [1e3 * w_exact * r for r in ramp], "k--",
        label="exact quasi-static, $q\\,s(t)\\,w(a/32)$")
ax.set_xlabel("time (s)")
ax.set_ylabel("settlement of the centre point (mm)")
ax.set_title("Uniform circular load on an elastic half-space")
ax.legend(fontsize=8, loc="lower right")
fig.tight_layout()
fig.savefig(os.path.join(here, "halfspace.png"), dpi=120)
