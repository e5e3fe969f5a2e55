#!/usr/bin/env python3
"""Side profiles of the Taylor rod (profile_*.csv of taylor_profile.py): 3D solid,
axisymmetric dashed, one colour per time."""
import csv
import glob
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

here = os.path.dirname(os.path.abspath(__file__))
fig, ax = plt.subplots(figsize=(4.2, 6.0))
colors = {}  # one colour per time, 3D solid, axisymmetric dashed
for path in sorted(glob.glob(os.path.join(here, "profile_*.csv"))):
    with open(path, newline="") as f:
        rows = [(float(r["height"]), float(r["radius"])) for r in csv.DictReader(f)]
    run, time = os.path.basename(path)[len("profile_"):-len(".csv")].split("_")
    axisymmetric = run == "axisymmetric"
    label = f"{'axisymmetric' if axisymmetric else run.upper()}, {int(time[:-2])} µs"
    ax.plot([1e3 * r for _, r in rows], [1e3 * h for h, _ in rows], label=label,
            linestyle="--" if axisymmetric else "-",
            color=colors.setdefault(time, f"C{len(colors)}"))
ax.axvspan(7.0, 7.1, color="0.85", label="literature foot radius")
ax.axhspan(21.4, 21.7, color="0.92", label="literature final length")
ax.set_xlabel("radius (mm)")
ax.set_ylabel("height above the wall (mm)")
ax.set_xlim(0, 8)
ax.set_ylim(0, 33)
ax.legend(fontsize=7, loc="upper right")
ax.set_title("Taylor impact, copper at 227 m/s")
fig.tight_layout()
fig.savefig(os.path.join(here, "profiles.png"), dpi=120)
