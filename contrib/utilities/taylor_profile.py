#!/usr/bin/env python3
"""Final length, foot radius and side profile of a Taylor-impact rod.

Usage: taylor_profile.py PARTICLES_CSV [--axisymmetric] [--spacing H]
                         [--profile OUT.csv] [--plane-rows INITIAL_CSV]

The rod's axis is y with the wall at y = 0; its radius is sqrt(x^2 + z^2)
in 3D and x in an axisymmetric run (x = r, y = z). Length and foot radius
are the largest y and radius of a point plus half the initial point
spacing H (default 0.2 mm), the extent of the point's own domain. The
profile is the largest radius in slices of height H along the axis.

With --plane-rows (3D quarter rods) only the points that started in the
row next to a symmetry plane (x < H or z < H in INITIAL_CSV, the file at
t = 0, matched by id) count. Their radial positions are those of an
axisymmetric run's points (H/2, 3H/2, ...), so the two runs measure the
same way: over all points, the square lattice in the circle has points
whose radius plus H/2 exceeds the rod's radius (3.30 mm for 3.2 mm).
"""
import argparse
import csv
import math
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("csv_file")
    parser.add_argument("--axisymmetric", action="store_true")
    parser.add_argument("--spacing", type=float, default=2e-4)
    parser.add_argument("--profile", help="write height, radius to this file")
    parser.add_argument("--plane-rows", metavar="INITIAL_CSV",
                        help="3D: only the points that started next to a "
                        "symmetry plane in this file")
    args = parser.parse_args()
    if args.plane_rows and args.axisymmetric:
        sys.exit("--plane-rows is for 3D runs")
    kept = None
    if args.plane_rows:
        with open(args.plane_rows, newline="") as f:
            kept = {row["id"] for row in csv.DictReader(f)
                    if min(abs(float(row["x"])), abs(float(row["z"])))
                    < args.spacing}
    heights, radii = [], []
    with open(args.csv_file, newline="") as f:
        for row in csv.DictReader(f):
            if kept is not None and row["id"] not in kept:
                continue
            x, y = float(row["x"]), float(row["y"])
            z = 0.0 if args.axisymmetric else float(row["z"])
            heights.append(y)
            radii.append(abs(x) if args.axisymmetric else math.hypot(x, z))
    if not heights:
        sys.exit(f"{args.csv_file}: no points")
    half = 0.5 * args.spacing
    length = max(heights) + half
    foot = max(r for r, y in zip(radii, heights) if y < 2 * args.spacing) + half
    print(f"points {len(heights)}  final length {length * 1e3:.3f} mm  "
          f"foot radius {foot * 1e3:.3f} mm")
    if args.profile:
        n = int(length / args.spacing) + 1
        largest = [0.0] * n
        for r, y in zip(radii, heights):
            i = min(max(int(y / args.spacing), 0), n - 1)
            largest[i] = max(largest[i], r + half)
        with open(args.profile, "w") as out:
            out.write("height,radius\n")
            for i, r in enumerate(largest):
                if r > 0:
                    out.write(f"{(i + 0.5) * args.spacing:.6e},{r:.6e}\n")


if __name__ == "__main__":
    main()
