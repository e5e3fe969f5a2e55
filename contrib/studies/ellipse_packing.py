#!/usr/bin/env python3
"""Deterministic placement of axis-aligned ellipses in a box (seed 004
Fig. 6, the ellipse compaction).

Places N non-overlapping axis-aligned ellipses in a W x H box (mm) with a
clear gap of at least G between any two ellipses and between an ellipse and
the box walls, and prints the 'Body N' and 'Material N' subsections of
parameters/ellipse_compaction.prm (SI units: mm -> m), one body and one
material per ellipse.

Algorithm (pseudo-random with a fixed seed, so the output is reproducible):
random semi-axes (aspect ratio 1.2-2.2, half of them wide, half tall) are
placed largest first by random sequential addition (an ellipse that finds no
place in 4000 tries shrinks by 5 %); then Monte Carlo compaction: each sweep
moves every ellipse by a small random step and grows it by 2 % when the
result keeps the gaps, until the filled fraction of the box reaches the
target or stops growing for 100 sweeps. The gap test is exact up to the
boundary sampling (< 1 um for the final check): an ellipse is clear of another when no sample of either
boundary lies inside the other and the smallest distance between the
sampled boundaries is at least G. Values are rounded to 0.1 um and checked
again after rounding.

Usage::

    ellipse_packing.py [--count 20] [--fill 0.6] [--gap 0.03] [--seed 4]
                       [--width 1] [--height 2]
"""

import argparse
import math
import random

import numpy as np

SAMPLES = 128        # boundary samples while placing
FINAL_SAMPLES = 2048  # boundary samples of the final check (< 1 um apart)


def boundary(ellipse, samples):
    cx, cy, a, b = ellipse
    t = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    return np.stack([cx + a * np.cos(t), cy + b * np.sin(t)], axis=1)


def inside(points, ellipse):
    cx, cy, a, b = ellipse
    return ((points[:, 0] - cx) / a) ** 2 + ((points[:, 1] - cy) / b) ** 2 < 1


def clear(e1, e2, gap, samples=SAMPLES):
    """True when the smallest distance between e1 and e2 is at least gap."""
    d = math.hypot(e1[0] - e2[0], e1[1] - e2[1])
    if d > max(e1[2], e1[3]) + max(e2[2], e2[3]) + gap:
        return True
    if d < min(e1[2], e1[3]) + min(e2[2], e2[3]):
        return False
    p1, p2 = boundary(e1, samples), boundary(e2, samples)
    if inside(p1, e2).any() or inside(p2, e1).any():
        return False
    # sampling makes the distance up to (spacing/2)^2/(2 R) too large: a
    # margin of a quarter spacing covers it
    spacing = 2 * math.pi * max(e1[2], e1[3], e2[2], e2[3]) / samples
    distances = np.sqrt(((p1[:, None, :] - p2[None, :, :]) ** 2).sum(axis=2))
    return distances.min() >= gap + 0.25 * spacing


def in_box(e, width, height, gap):
    cx, cy, a, b = e
    return (cx - a >= gap and cx + a <= width - gap and cy - b >= gap
            and cy + b <= height - gap)


def fits(e, others, width, height, gap, samples=SAMPLES):
    return in_box(e, width, height, gap) and all(
        clear(e, o, gap, samples) for o in others)


def area(ellipses):
    return sum(math.pi * a * b for _, _, a, b in ellipses)


def place(count, fill, gap, seed, width, height):
    rng = random.Random(seed)
    # sizes: equal areas up to +-40 %, scaled so that they add up to 45 % of
    # the box before the compaction grows them
    shapes = []
    for i in range(count):
        aspect = rng.uniform(1.2, 2.2)
        weight = rng.uniform(0.6, 1.4)
        wide = i % 2 == 0
        shapes.append((weight, aspect, wide))
    total = sum(w for w, _, _ in shapes)
    ellipses = []
    for weight, aspect, wide in sorted(shapes, reverse=True):
        target = 0.45 * width * height * weight / total
        minor = math.sqrt(target / (math.pi * aspect))
        a, b = (aspect * minor, minor) if wide else (minor, aspect * minor)
        while True:
            placed = False
            for _ in range(4000):
                e = (rng.uniform(a + gap, width - a - gap),
                     rng.uniform(b + gap, height - b - gap), a, b)
                if fits(e, ellipses, width, height, gap):
                    ellipses.append(e)
                    placed = True
                    break
            if placed:
                break
            a, b = 0.95 * a, 0.95 * b
    # Monte Carlo compaction: jiggle and grow
    step = 0.02
    sweep = last_growth = 0
    best = area(ellipses)
    while (area(ellipses) < fill * width * height
           and sweep - last_growth < 100):
        sweep += 1
        if area(ellipses) > best:
            best, last_growth = area(ellipses), sweep
        for i in range(len(ellipses)):
            cx, cy, a, b = ellipses[i]
            others = ellipses[:i] + ellipses[i + 1:]
            grow = 1.02 if area(ellipses) < fill * width * height else 1.0
            for factor in (grow, 1.0):
                e = (cx + rng.uniform(-step, step),
                     cy + rng.uniform(-step, step), a * factor, b * factor)
                if fits(e, others, width, height, gap):
                    ellipses[i] = e
                    break
    return ellipses, sweep


def rounded(ellipses):
    """Centres and semi-axes rounded to 0.1 um (written as metres with 7
    significant digits below 1 mm)."""
    return [tuple(round(v, 4) for v in e) for e in ellipses]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=20)
    parser.add_argument("--fill", type=float, default=0.6)
    parser.add_argument("--gap", type=float, default=0.03,
                        help="clear gap between ellipses and to the walls, mm")
    parser.add_argument("--seed", type=int, default=4)
    parser.add_argument("--width", type=float, default=1.0)
    parser.add_argument("--height", type=float, default=2.0)
    args = parser.parse_args()

    ellipses, sweeps = place(args.count, args.fill, args.gap, args.seed,
                             args.width, args.height)
    # bottom to top, then left to right: body numbers read like the picture
    ellipses = rounded(sorted(ellipses, key=lambda e: (round(e[1], 1), e[0])))
    for i, e in enumerate(ellipses):
        others = ellipses[:i] + ellipses[i + 1:]
        assert fits(e, others, args.width, args.height, args.gap,
                    FINAL_SAMPLES), f"ellipse {i} violates the gap"
    fraction = area(ellipses) / (args.width * args.height)
    print(f"# generated by contrib/studies/ellipse_packing.py --count "
          f"{args.count} --fill {args.fill} --gap {args.gap} --seed "
          f"{args.seed} --width {args.width} --height {args.height}")
    print(f"# {len(ellipses)} ellipses, area fraction {fraction:.3f} "
          f"({sweeps} compaction sweeps), clear gap >= {args.gap} mm between "
          f"ellipses and to the walls")
    print("# body: centre x, y; semi-axes a, b (mm)")
    for i, (cx, cy, a, b) in enumerate(ellipses):
        print(f"#   {i:2d}: {cx:.4f}, {cy:.4f}; {a:.4f}, {b:.4f}")
    for i, (cx, cy, a, b) in enumerate(ellipses):
        print(f"subsection Body {i}")
        print("  set Shape        = ellipsoid")
        print(f"  set Center       = {cx * 1e-3:.7g}, {cy * 1e-3:.7g}")
        print(f"  set Half lengths = {a * 1e-3:.7g}, {b * 1e-3:.7g}")
        print(f"  set Material     = {i}")
        print("end")
    for i in range(len(ellipses)):
        print(f"subsection Material {i}")
        print("  set Model name = neo hookean")
        print("  set Density    = 2780")
        print("  subsection Neo hookean")
        print("    set Bulk modulus  = 7.809e10")
        print("    set Shear modulus = 2.76e10")
        print("  end")
        print("end")


if __name__ == "__main__":
    main()
