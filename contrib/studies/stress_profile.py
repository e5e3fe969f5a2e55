#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
"""Plot a point field (default: the axial stress sigma_xx) against x from
fmpm's particle VTU output of several runs at one output time.

    stress_profile.py --output stress.png --time 0.08 \
        "classic=out_classic" "cpGIMP=out_cpgimp" [--field stress_0]

Each run directory must hold particles.pvd and its serial or parallel
.vtu pieces (zlib-compressed binary, as deal.II writes them). Shows the
cell-crossing noise of classic shape functions (issue 7).
"""

import argparse
import base64
import os
import re
import struct
import sys
import zlib


def decode_array(text, dtype):
    """deal.II's binary DataArray: base64(header) + base64(zlib blocks)."""
    text = text.strip()
    n_blocks = struct.unpack("<4I", base64.b64decode(text[:24]))[0]
    header_chars = 4 * ((4 * (3 + n_blocks) + 2) // 3)
    header = base64.b64decode(text[:header_chars])
    values = struct.unpack("<%dI" % (3 + n_blocks), header)
    sizes = values[3:]
    data = base64.b64decode(text[header_chars:])
    raw = b""
    offset = 0
    for size in sizes:
        raw += zlib.decompress(data[offset:offset + size])
        offset += size
    code = {"Float32": "f", "Float64": "d", "Int32": "i", "UInt8": "B"}[dtype]
    count = len(raw) // struct.calcsize(code)
    return struct.unpack("<%d%s" % (count, code), raw)


def read_vtu(path, field):
    content = open(path).read()
    arrays = re.findall(r'<DataArray type="(\w+)"([^>]*)>(.*?)</DataArray>',
                        content, re.S)
    points = None
    values = None
    for dtype, attributes, text in arrays:
        name = re.search(r'Name="([^"]*)"', attributes)
        if name is None and points is None:
            points = decode_array(text, dtype)
        elif name is not None and name.group(1) == field:
            values = decode_array(text, dtype)
    if points is None or values is None:
        sys.exit("%s: no points or no field '%s'" % (path, field))
    return points[0::3], values


def pieces_at(directory, time):
    """The .vtu pieces of the output closest to time."""
    pvd = open(os.path.join(directory, "particles.pvd")).read()
    records = re.findall(r'timestep="([^"]*)"[^>]*file="([^"]*)"', pvd)
    if not records:
        sys.exit("%s: no records in particles.pvd" % directory)
    step, name = min(records, key=lambda r: abs(float(r[0]) - time))
    path = os.path.join(directory, name)
    if name.endswith(".pvtu"):
        content = open(path).read()
        return float(step), [os.path.join(directory, p) for p in
                             re.findall(r'<Piece Source="([^"]*)"', content)]
    return float(step), [path]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("runs", nargs="+", help="LABEL=DIRECTORY")
    parser.add_argument("--time", type=float, required=True)
    parser.add_argument("--field", default="stress_0")
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
        time, pieces = pieces_at(directory, arguments.time)
        x, v = [], []
        for piece in pieces:
            px, pv = read_vtu(piece, arguments.field)
            x += px
            v += pv
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
