#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
"""Plot a point field (default: the axial stress sigma_xx) against x from
fmpm's particle VTU output of several runs at one output time.

    stress_profile.py --output stress.png --time 0.08 \
        "classic=out_classic" "cpGIMP=out_cpgimp" [--field stress:0]

Each run directory must hold particles.pvd and its serial or parallel
.vtu pieces (zlib-compressed binary, as deal.II writes them). Shows the
cell-crossing noise of classic shape functions.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                "..", "utilities"))
import fmpm_vtu  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="LABEL=DIRECTORY")
    parser.add_argument("--time", type=float, required=True)
    parser.add_argument("--field", default="stress:0",
                        help="NAME or NAME:COMPONENT (default stress:0, sigma_xx)")
    parser.add_argument("--output", default="stress_profile.png")
    parser.add_argument("--title", default="")
    arguments = parser.parse_args()

    try:
        import matplotlib
    except ImportError:  # pyenv interpreter: Debian's python3-matplotlib
        sys.path.append("/usr/lib/python3/dist-packages")
        import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 4.5))
    markers = "os^vDx"
    for index, run in enumerate(arguments.runs):
        label, directory = run.split("=", 1)
        time, x, _, _, values = fmpm_vtu.read_output(
            directory, arguments.time, [arguments.field])
        v = values[arguments.field]
        order = sorted(range(len(x)), key=lambda i: x[i])
        axes.plot([x[i] for i in order], [v[i] for i in order],
                  marker=markers[index % len(markers)], markersize=3,
                  linewidth=0.8, label="%s (t = %.3g s)" % (label, time))
    axes.set_xlabel("x (m)")
    axes.set_ylabel(arguments.field)
    axes.grid(True, alpha=0.3)
    axes.legend()
    if arguments.title:
        axes.set_title(arguments.title)
    figure.tight_layout()
    figure.savefig(arguments.output, dpi=110)
    print("wrote", arguments.output)


if __name__ == "__main__":
    main()
