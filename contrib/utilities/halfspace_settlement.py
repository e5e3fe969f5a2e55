#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Centre settlement of parameters/circular_load_halfspace.prm against the half-space.

Usage: halfspace_settlement.py HISTORY_CSV [--q 1e4] [--a 1] [--E 1e7]
                               [--nu 0.3] [--depth D]

Reads the last row of history.csv (track1_uy: the vertical displacement of
the tracked point nearest the centre, at depth D, default a/32) and prints
it against the exact displacement of a uniformly loaded circle on an
elastic half-space on its axis,
    w(d) = q (1 + nu)/E (2 (1 - nu)(sqrt(a^2 + d^2) - d)
                         + d (1 - d/sqrt(a^2 + d^2))),
whose value at the surface is w0 = 2 q a (1 - nu^2)/E, and the kinetic
energy left as a fraction of the strain energy. Exit status 1 when the
settlement is more than 2 % off.
"""
import argparse
import csv
import math
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("history")
    parser.add_argument("--q", type=float, default=1e4)
    parser.add_argument("--a", type=float, default=1.0)
    parser.add_argument("--E", type=float, default=1e7)
    parser.add_argument("--nu", type=float, default=0.3)
    parser.add_argument("--depth", type=float, default=None)
    args = parser.parse_args()
    q, a, E, nu = args.q, args.a, args.E, args.nu
    d = a / 32 if args.depth is None else args.depth
    with open(args.history) as f:
        rows = list(csv.DictReader(l for l in f if not l.startswith("#")))
    last = rows[-1]
    s = math.sqrt(a * a + d * d)
    exact = q * (1 + nu) / E * (2 * (1 - nu) * (s - d) + d * (1 - d / s))
    w0 = 2 * q * a * (1 - nu * nu) / E
    w = -float(last["track1_uy"])
    error = w / exact - 1
    kinetic = float(last["kinetic_energy"]) / float(last["strain_energy"])
    print(f"t = {float(last['time']):.4g} s: settlement at depth {d:.4g} m "
          f"{w * 1e3:.5f} mm, exact {exact * 1e3:.5f} mm ({error:+.2%}); "
          f"surface w0 = 2 q a (1 - nu^2)/E = {w0 * 1e3:.5f} mm "
          f"({w / w0 - 1:+.2%}); kinetic/strain energy {kinetic:.2e}")
    return 0 if abs(error) <= 0.02 else 1


if __name__ == "__main__":
    sys.exit(main())
