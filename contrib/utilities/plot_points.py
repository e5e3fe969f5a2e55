#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
"""Picture of a run's material points at one output time, coloured by body
(or by any point field), for the doc pages: reads OUTPUT_DIR/particles.pvd
and its VTU pieces directly (matplotlib; no ParaView needed).

    plot_points.py OUTPUT_DIR [--time T] [--field body_id | stress:0 | ...]
                   [--view xy|xz|yz] [--output points.png]

In ParaView the same picture: open OUTPUT_DIR/particles.pvd, Representation
'Point Gaussian' (or 'Points'), Coloring 'body_id'; stress and
deformation_gradient are tensors (components XX, XY, ...), velocity a
vector.
"""

import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import fmpm_vtu  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="the run's output directory")
    parser.add_argument("--time", type=float, default=float("inf"),
                        help="output time (default: the last output)")
    parser.add_argument("--field", default="body_id",
                        help="NAME or NAME:COMPONENT (default body_id)")
    parser.add_argument("--view", default="xy", choices=["xy", "xz", "yz"],
                        help="projection plane for 3D runs (default xy)")
    parser.add_argument("--output", default="points.png")
    args = parser.parse_args()
    step, x, y, z, values = fmpm_vtu.read_output(args.directory, args.time,
                                                 [args.field])
    coordinates = {"x": x, "y": y, "z": z}
    horizontal, vertical = coordinates[args.view[0]], coordinates[args.view[1]]
    try:
        import matplotlib
    except ImportError:  # another interpreter: Debian's python3-matplotlib
        sys.path.append("/usr/lib/python3/dist-packages")
        try:
            import matplotlib
        except ImportError:
            sys.exit("plot_points.py: needs matplotlib (apt-get install "
                     "python3-matplotlib)")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axes = plt.subplots(figsize=(7, 5))
    categorical = args.field in ("body_id", "material_id")
    scatter = axes.scatter(horizontal, vertical, c=values[args.field], s=4,
                           cmap="tab10" if categorical else "viridis",
                           vmin=0 if categorical else None,
                           vmax=9 if categorical else None)
    if not categorical:
        figure.colorbar(scatter, ax=axes, label=args.field)
    axes.set_aspect("equal")
    axes.set_xlabel(args.view[0] + " (m)")
    axes.set_ylabel(args.view[1] + " (m)")
    axes.set_title("%s, t = %.4g s, coloured by %s"
                   % (os.path.basename(os.path.normpath(args.directory)),
                      step, args.field))
    figure.tight_layout()
    figure.savefig(args.output, dpi=120)
    print("wrote %s (%d points at t = %g)" % (args.output, len(x), step))


if __name__ == "__main__":
    main()
