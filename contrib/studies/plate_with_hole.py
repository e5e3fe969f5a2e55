#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
"""The stress concentration at a hole in a plate under tension (Kirsch's
problem) against the cell size: runs parameters/plate_with_hole.prm at
several resolutions and charts sigma_xx at the top of the hole over the
far-field traction.

    plate_with_hole.py [--fmpm PATH] [--output DIR] [--cells 24 48 96 192]
                       [--shape-functions classic ugimp] [--plot-only]

For each number of cells n (over the mesh's 1.2 m) the run's last
particles CSV gives two measures at the top of the hole (0, a):
  * 'nearest point': sigma_xx of the point of the first column (x = h/4)
    nearest the hole;
  * 'fitted to the edge': the first column's sigma_xx for y in [a, 2a]
    fitted by least squares to c0 + c1 (a/y)^2 + c2 (a/y)^4 (the terms of
    Kirsch's solution along x = 0) and taken at y = a.
Each shape function's runs go to <DIR>/<shape function>/cells_<n>/.
Writes <DIR>/results.csv and <DIR>/plate_with_hole.png. Kirsch's factor is
3 for an infinite plate; Heywood's finite-width correction for a hole of
diameter d in a strip of width D, K = (2 + (1 - d/D)^3) / (1 - d/D) on the
gross stress, gives 3.03 for d/D = a/W = 0.1.
"""

import argparse
import csv
import os
import subprocess
import sys
import time

REPOSITORY = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SCENE = os.path.join(REPOSITORY, "parameters", "plate_with_hole.prm")
RADIUS = 0.1
HALF_WIDTH = 1.0
SIGMA0 = 1e4
MESH_EXTENT = 1.2


def heywood(d_over_w):
    """Gross-stress concentration of a central hole in a finite strip."""
    return (2 + (1 - d_over_w) ** 3) / (1 - d_over_w)


def override_text(n, directory, shape_function, traction):
    spacing = MESH_EXTENT / n / 2
    return "\n".join([
        "subsection Mesh",
        "  set Subdivisions = %d, %d" % (n, n),
        "end",
        "subsection Shape function",
        "  set Type = %s" % shape_function,
        "end",
        "subsection Boundary conditions",
        "  subsection Traction 0",
        # The last column of points only.
        "    set Box lower corner = %.12g, 0" % (HALF_WIDTH - 0.75 * spacing),
        "    set Function constants = s0=%.12g" % traction,
        "  end",
        "end",
        "subsection Output",
        "  set Directory = %s" % directory,
        "end",
        ""])


def last_particles(directory):
    files = sorted(f for f in os.listdir(directory)
                   if f.startswith("particles_") and f.endswith(".csv"))
    return os.path.join(directory, files[-1])


def measure(directory, n):
    import numpy as np
    traction = SIGMA0
    with open(os.path.join(directory, "override.prm")) as f:
        for line in f:
            if "s0=" in line:
                traction = float(line.split("s0=")[1])
    spacing = MESH_EXTENT / n / 2
    x, y, sxx = [], [], []
    with open(last_particles(directory)) as f:
        for row in csv.DictReader(f):
            x.append(float(row["x"]))
            y.append(float(row["y"]))
            sxx.append(float(row["stress_xx"]))
    x, y, sxx = np.array(x), np.array(y), np.array(sxx) / traction
    first_column = (x < spacing) & (y < 2 * RADIUS)
    yc, sc = y[first_column], sxx[first_column]
    nearest = sc[np.argmin(yc)]
    basis = np.vstack([np.ones_like(yc), (RADIUS / yc) ** 2,
                       (RADIUS / yc) ** 4]).T
    coefficients = np.linalg.lstsq(basis, sc, rcond=None)[0]
    fitted = coefficients.sum()
    return nearest, fitted


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--fmpm", default=os.path.join(
        REPOSITORY, "build", "applications", "fmpm", "fmpm"))
    parser.add_argument("--output", default="study_plate_with_hole")
    parser.add_argument("--cells", type=int, nargs="+",
                        default=[24, 48, 96, 192])
    parser.add_argument("--shape-functions", nargs="+",
                        default=["classic", "ugimp"])
    parser.add_argument("--plot-only", action="store_true")
    parser.add_argument("--traction", type=float, default=SIGMA0,
                        help="far-field traction sigma0 (Pa); a smaller one "
                        "keeps the loaded edge's points from crossing a "
                        "cell face on fine meshes (linear: the ratio is the "
                        "same)")
    arguments = parser.parse_args()
    os.makedirs(arguments.output, exist_ok=True)

    results = []
    for shape_function in arguments.shape_functions:
        for n in arguments.cells:
            directory = os.path.abspath(os.path.join(
                arguments.output, shape_function, "cells_%d" % n))
            os.makedirs(directory, exist_ok=True)
            if not arguments.plot_only:
                override = os.path.join(directory, "override.prm")
                with open(override, "w") as f:
                    f.write(override_text(n, directory, shape_function,
                                          arguments.traction))
                start = time.time()
                with open(os.path.join(directory, "log.txt"), "w") as log:
                    subprocess.run([arguments.fmpm, SCENE, override],
                                   stdout=log, stderr=subprocess.STDOUT,
                                   check=True)
                with open(os.path.join(directory, "wall_time.txt"), "w") as f:
                    f.write("%.1f\n" % (time.time() - start))
            elif not any(f.startswith("particles_")
                         for f in os.listdir(directory)):
                continue  # --plot-only: a run not made (yet)
            nearest, fitted = measure(directory, n)
            cell = MESH_EXTENT / n
            results.append((shape_function, n, cell, RADIUS / cell, nearest,
                            fitted))
            print("%-8s n = %4d  h = %.5f m  a/h = %5.2f  nearest point "
                  "%.4f  fitted to the edge %.4f" % results[-1], flush=True)

    expected = heywood(RADIUS / HALF_WIDTH)
    with open(os.path.join(arguments.output, "results.csv"), "w") as f:
        f.write("shape_function,cells,cell_size,radius_over_cell,"
                "nearest_point,fitted_to_edge,heywood,error_fitted\n")
        for shape_function, n, cell, ratio, nearest, fitted in results:
            f.write("%s,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n"
                    % (shape_function, n, cell, ratio, nearest, fitted,
                       expected, fitted / expected - 1))

    try:
        import matplotlib
    except ImportError:  # pyenv interpreter: Debian's python3-matplotlib
        sys.path.append("/usr/lib/python3/dist-packages")
        import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7, 4.5))
    for index, shape_function in enumerate(arguments.shape_functions):
        rows = [r for r in results if r[0] == shape_function]
        ratios = [r[3] for r in rows]
        axes.plot(ratios, [r[5] for r in rows], "o-", color="C%d" % index,
                  label="%s, fitted to the hole's edge" % shape_function)
        axes.plot(ratios, [r[4] for r in rows], "s--", color="C%d" % index,
                  alpha=0.6, label="%s, point nearest the edge"
                  % shape_function)
    axes.axhline(3, color="k", linewidth=0.8, label="Kirsch (infinite plate)")
    axes.axhline(expected, color="C3", linewidth=0.8,
                 label="Heywood, a/W = 0.1: %.3f" % expected)
    axes.axhspan(0.95 * expected, 1.05 * expected, color="C3", alpha=0.1,
                 label="within 5 %")
    axes.set_xscale("log", base=2)
    ratios = sorted(set(r[3] for r in results))
    axes.set_xticks(ratios)
    axes.set_xticklabels(["%g" % r for r in ratios])
    axes.set_xlabel("hole radius / cell size a/h (2 x 2 points per cell)")
    axes.set_ylabel(r"$\sigma_{xx}(0, a) / \sigma_0$")
    axes.set_title("Plate with a hole under tension")
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(os.path.join(arguments.output, "plate_with_hole.png"),
                   dpi=110)


if __name__ == "__main__":
    main()
