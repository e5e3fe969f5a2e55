#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Simple shear of a neo-Hookean block to gamma = 1, periodic in x.

Runs parameters/simple_shear.prm (fixed bottom, top moved along x, periodic
sides) once per method, and the same block with free sides (no periodic
direction) for contrast, and draws doc/studies/simple_shear.png: the volume
average <sigma_xy> over the material points (particles_NNNNN.csv: sum of
J sigma_xy over sum of J, every point having the same initial volume)
against the shear gamma(t) = s(t)/H of the top, with G gamma, and the error
<sigma_xy>/(G gamma) - 1. Writes simple_shear.csv and prints a Markdown
table (<sigma_xy> at the end, largest |J - 1|, the reference solution's
relative L2 displacement error, steps and wall time from summary.json).

    contrib/studies/simple_shear.py [--fmpm PATH] [--output DIR]
"""

import argparse
import csv
import json
import math
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
# The scene's constants (parameters/simple_shear.prm).
G, H, V, T0 = 100.0, 1.0, 0.25, 1.0
N_ROWS = 8  # node rows above the bottom (Mesh/Subdivisions in y)

FMPM = "subsection Mass matrix\n set Model name = fmpm\n" \
       " subsection Fmpm\n  set Order = {}\n end\nend\n"


def particle_update(name):
    return "subsection Particle update\n set Model name = " + name + "\nend\n"


def kinematic_walls():
    """Every node row y_j = j H / N_ROWS above the bottom moves with
    v_x = (v(t)/H) y_j (a region wall per row; the top row is the scene's
    wall 0); the top and bottom keep v_y = 0."""
    text = "set Number of moving walls = {}\n".format(N_ROWS)
    text += "subsection Boundary conditions\n"
    for j in range(1, N_ROWS):
        y = j * H / N_ROWS
        text += (" subsection Moving wall {}\n"
                 "  set Boundary ids =\n"
                 "  set Region = {} - abs(y - {})\n"
                 "  set Direction = 1, 0\n"
                 "  set Velocity = (t < t0 ? V*(1 - cos(pi*t/t0))/2 : V)*{}\n"
                 "  set Function constants = V={}, t0={}, "
                 "pi=3.141592653589793\n"
                 " end\n").format(j, 0.25 * H / N_ROWS, y, y / H, V, T0)
    return text + "end\n"


FREE_SIDES = ("subsection Mesh\n set Periodic directions =\n"
              " set Lower corner = -1, 0\n set Upper corner = 2, 1\n"
              " set Subdivisions = 24, 8\nend\n")

METHODS = [
    ("FLIP", ""),
    ("PIC", particle_update("pic")),
    ("XPIC(5)", particle_update("xpic") + FMPM.format(5)),
    ("FMPM(5)", particle_update("fmpm") + FMPM.format(5)),
    ("FMPM, full mass matrix", particle_update("fmpm") +
     "subsection Mass matrix\n set Model name = full\nend\n"),
    ("FLIP, kinematic (every node row)", kinematic_walls()),
    ("FLIP, free sides", FREE_SIDES),
]


def shear(t):
    """gamma(t) = s(t)/H of the top (the wall's displacement)."""
    if t < T0:
        return V * (t / 2 - T0 / (2 * math.pi) * math.sin(math.pi * t / T0)) / H
    return V * (t - T0 / 2) / H


def averages(directory):
    """(gamma, <sigma_xy>, max |J - 1|) at each output."""
    times = [float(row["time"])
             for row in csv.DictReader(open(directory / "history.csv"))]
    result = []
    for n, t in enumerate(times):
        name = directory / "particles_{:05d}.csv".format(n)
        if not name.exists():
            break
        rows = list(csv.DictReader(open(name)))
        volume = sum(float(r["J"]) for r in rows)
        sigma = sum(float(r["J"]) * float(r["stress_xy"]) for r in rows)
        j_error = max(abs(float(r["J"]) - 1) for r in rows)
        result.append((shear(t), sigma / volume, j_error))
    return result


def import_pyplot():
    try:
        import matplotlib
    except ImportError:
        sys.path.append("/usr/lib/python3/dist-packages")
        import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    return pyplot


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmpm",
                        default=str(ROOT / "build/applications/fmpm/fmpm"))
    parser.add_argument("--output", default="study_simple_shear")
    parser.add_argument("--chart",
                        default=str(ROOT / "doc/studies/simple_shear.png"))
    arguments = parser.parse_args()
    output = Path(arguments.output)
    output.mkdir(parents=True, exist_ok=True)
    curves = {}
    table = []
    for number, (label, override) in enumerate(METHODS):
        directory = (output / "run_{}".format(number)).resolve()
        override_file = output / "run_{}.prm".format(number)
        override_file.write_text(
            override + "subsection Output\n set Directory = {}\n"
            " set Write particle csv = true\n set Interval = 0.1\nend\n"
            "subsection Timer\n set Type = none\nend\n".format(directory))
        status = subprocess.run(
            [arguments.fmpm, str(ROOT / "parameters/simple_shear.prm"),
             str(override_file)],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
        summary = json.load(open(directory / "summary.json"))
        curve = averages(directory)
        curves[label] = curve
        gamma, sigma, _ = curve[-1]
        table.append((label, gamma, sigma, sigma / (G * gamma) - 1,
                      max(c[2] for c in curve),
                      summary["error_displacement_l2"], summary["n_steps"],
                      summary["wall_seconds"], status))

    with open(output / "simple_shear.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["method", "gamma_end", "sigma_xy_end",
                         "relative_error", "max_J_error",
                         "error_displacement_l2", "steps", "wall_s",
                         "exit_status"])
        writer.writerows(table)
    print("| method | gamma reached | <sigma_xy> (Pa) | <sigma_xy>/(G gamma) - 1"
          " | max abs(J - 1) | displacement error | steps | wall (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for (label, gamma, sigma, error, j_error, u_error, steps, wall,
         status) in table:
        print("| {} | {:.3f}{} | {:.3f} | {:+.2e} | {:.1e} | {:.1e} | {} "
              "| {:.2f} |".format(
                  label, gamma, "" if status == 0 else " (failed)", sigma,
                  error, j_error, u_error, steps, wall))

    pyplot = import_pyplot()
    figure, (left, right) = pyplot.subplots(1, 2, figsize=(11, 4.5))
    gammas = [i / 100 for i in range(101)]
    left.plot(gammas, [G * g for g in gammas], "k-", lw=3, alpha=0.3,
              label="G gamma (exact)")
    for label, curve in curves.items():
        left.plot([c[0] for c in curve], [c[1] for c in curve], ".-",
                  label=label)
        right.plot([c[0] for c in curve if c[0] > 0.02],
                   [abs(c[1] / (G * c[0]) - 1) for c in curve if c[0] > 0.02],
                   ".-", label=label)
    left.set_xlabel("shear gamma")
    left.set_ylabel("<sigma_xy> (Pa)")
    left.set_title("Volume-averaged shear stress")
    left.legend(fontsize=8)
    right.axhline(0.01, color="k", ls="--", lw=1, label="1 %")
    right.set_yscale("log")
    right.set_xlabel("shear gamma")
    right.set_ylabel("|<sigma_xy>/(G gamma) - 1|")
    right.set_title("Relative error")
    right.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(arguments.chart, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
