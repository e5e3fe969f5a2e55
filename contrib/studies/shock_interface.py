#!/usr/bin/env python3
"""Stresses of a shock through a perfect interface against one material.

Reads a study made with fmpm_study.py from
parameters/shock_nickel_interface.prm (seed 004 Fig. 7): for every
multimaterial run, the points' sigma_xx in the last particles_NNNNN.csv
against the single-material run (Label 'single') of the same particle
update and order, point by point (rows are sorted by id). Reports the
largest and the root-mean-square difference over the shocked points (|sigma|
above 5 % of the plateau), in percent of the plateau stress behind the
front.

Writes ``shock_interface.csv`` and ``shock_interface.png`` (left: the
sigma_xx profile along the bottom row near the front for XPIC(5), every
label; right: the largest difference against the order k) into the study's
output directory and prints the table in Markdown.

Usage::

    shock_interface.py STUDY_FILE [--output DIR] [--quick]
"""

import argparse
import csv
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fmpm_study  # noqa: E402

UPDATE = "Particle update/Model name"
ORDER = "Mass matrix/Fmpm/Order"


def last_particles(directory):
    """The columns of the run's last particles_NNNNN.csv, or None."""
    files = sorted(Path(directory).glob("particles_*.csv"))
    if not files:
        return None
    return np.genfromtxt(files[-1], delimiter=",", names=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study")
    parser.add_argument("--output")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()

    study = fmpm_study.parse_study(Path(args.study), quick=args.quick)
    output = Path(args.output) if args.output else \
        fmpm_study.default_output_dir(args.study, args.quick)
    runs = {}
    for run in fmpm_study.expand_runs(study, output):
        key = (run.swept.get("Label"), run.swept.get(UPDATE, "xpic"),
               int(run.swept.get(ORDER, 5)))
        runs[key] = last_particles(run.directory)

    rows = []
    for (label, update, k), points in sorted(runs.items()):
        if label == "single":
            continue
        reference = runs.get(("single", update, k))
        row = {"label": label, "update": update, "k": k,
               "max": None, "rms": None}
        if points is not None and reference is not None and \
                len(points) == len(reference) and \
                (points["id"] == reference["id"]).all():
            s, s0 = points["stress_xx"], reference["stress_xx"]
            x0 = reference["x"]
            plateau = np.abs(s0[(x0 > 0.03) & (x0 < 0.038)].mean())
            shocked = np.abs(s0) > 0.05 * plateau
            difference = np.abs(s - s0)[shocked] / plateau
            row["max"] = 100 * difference.max()
            row["rms"] = 100 * np.sqrt((difference ** 2).mean())
        rows.append(row)

    with open(output / "shock_interface.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["label", "particle_update", "k",
                         "max_difference_percent", "rms_difference_percent"])
        for r in rows:
            writer.writerow([r["label"], r["update"], r["k"]] + [
                "" if r[c] is None else f"{r[c]:.3g}" for c in ("max", "rms")])

    print("| update | k | contact | largest difference | rms difference |")
    print("|---|---|---|---|---|")
    for r in sorted(rows, key=lambda r: (r["update"], r["label"], r["k"])):
        print(f"| {r['update']} | {r['k']} | {r['label']} | " + " | ".join(
            "failed" if r[c] is None else f"{r[c]:.3g} %"
            for c in ("max", "rms")) + " |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, (profile, order) = plt.subplots(1, 2, figsize=(11, 4.2))
    interface = None
    for (label, update, k), points in sorted(runs.items()):
        if label == "single" and points is not None and interface is None:
            interface = 1e3 * points["x"][points["body"] == 0].max()
    for (label, update, k), points in sorted(runs.items()):
        if update != "xpic" or k != 5 or points is None:
            continue
        row = points["y"] == points["y"].min()
        x, s = points["x"][row], points["stress_xx"][row]
        keep = (x > 0.012) & (x < 0.03)
        order_x = np.argsort(x[keep])
        profile.plot(1e3 * x[keep][order_x], -1e-9 * s[keep][order_x],
                     label=label, linewidth=1)
    if interface is not None:
        profile.axvline(interface, color="k", linewidth=0.5, linestyle=":")
    profile.set_xlabel("x (mm); dotted: the interface (25 mm at rest)")
    profile.set_ylabel("-sigma_xx (GPa), bottom row of points")
    profile.set_title("XPIC(5), 4 us")
    profile.legend(fontsize=8)
    profile.grid(alpha=0.3)
    for label in dict.fromkeys(r["label"] for r in rows):
        for update in ("xpic", "fmpm"):
            series = sorted((r["k"], r["max"]) for r in rows
                            if r["label"] == label and r["update"] == update
                            and r["max"] is not None)
            if series:
                order.semilogy([k for k, _ in series],
                               [max(m, 1e-12) for _, m in series],
                               marker="o" if update == "xpic" else "s",
                               label=f"{update.upper()}(k) {label}")
    order.axhline(0.5, color="k", linewidth=0.5, linestyle="--")
    order.set_xlabel("k")
    order.set_ylabel("largest |sigma - sigma_single| (% of plateau)")
    order.set_title("against one material")
    order.legend(fontsize=7)
    order.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(output / "shock_interface.png", dpi=120)
    print(f"written: {output / 'shock_interface.csv'}, "
          f"{output / 'shock_interface.png'}")


if __name__ == "__main__":
    main()
