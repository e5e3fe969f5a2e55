#!/usr/bin/env python3
"""Contact times of a gap-closing study (seed 004 Fig. 2).

Reads a study made with fmpm_study.py from a two-block scene such as
parameters/two_blocks_gap.prm (its runs' history.csv), computes the average
axial stress of the points (sigma_yy, mass-weighted over the materials)
against time, and the contact time: the first time the bottom block's
(material 0's) average sigma_yy falls below half the impact stress
rho c v (linear interpolation between outputs). Compares it with the time
the gap closes, t_c = gap / v.

Writes ``contact_gap.csv`` (one row per run: method, placement, contact
time, error against t_c in percent) and ``contact_gap.png`` (the stress
against time near t_c, one panel per placement) into the study's output
directory, and prints the table in Markdown.

Usage::

    contact_time.py STUDY_FILE [--output DIR] [--quick] [--gap 0.0075]
                    [--speed 0.962] [--density 1000] [--wave-speed 1924]
"""

import argparse
import csv
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fmpm_study  # noqa: E402


def read_history(path):
    """The history.csv rows as dicts of floats."""
    with open(path, newline="") as stream:
        return [{k: fmpm_study.to_float(v) for k, v in row.items()}
                for row in csv.DictReader(stream)]


def average_axial_stress(row):
    """sigma_yy of the points, mass-weighted over the materials."""
    total = weighted = 0.0
    material = 0
    while f"mass_material_{material}" in row:
        mass = row[f"mass_material_{material}"]
        total += mass
        weighted += mass * row[f"stress_yy_material_{material}"]
        material += 1
    return weighted / total


def contact_time(rows, threshold):
    """First time material 0's sigma_yy falls below -threshold."""
    previous = None
    for row in rows:
        value = row["stress_yy_material_0"]
        if value < -threshold:
            if previous is None:
                return row["time"]
            t0, v0 = previous
            return t0 + (row["time"] - t0) * (-threshold - v0) / (value - v0)
        previous = (row["time"], value)
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study")
    parser.add_argument("--output")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--gap", type=float, default=0.0075)
    parser.add_argument("--speed", type=float, default=0.962)
    parser.add_argument("--density", type=float, default=1000.0)
    parser.add_argument("--wave-speed", type=float, default=1924.0)
    args = parser.parse_args()

    study = fmpm_study.parse_study(Path(args.study), quick=args.quick)
    output = Path(args.output) if args.output else \
        fmpm_study.default_output_dir(args.study, args.quick)
    runs = fmpm_study.expand_runs(study, output)
    t_c = args.gap / args.speed
    threshold = 0.5 * args.density * args.wave_speed * args.speed

    results = []
    for run in runs:
        history = run.directory / "history.csv"
        if not history.exists():
            print(f"{run.run_id}: no history.csv (not run?)", file=sys.stderr)
            continue
        rows = read_history(history)
        method = run.swept.get("Label", run.label())
        centre = run.swept.get("Body 0/Center", "")
        placement = ("mid cell" if centre.replace(" ", "").endswith("02625")
                     else "grid line")
        t = contact_time(rows, threshold)
        results.append({
            "run_id": run.run_id, "method": method, "placement": placement,
            "contact_time": t, "theory": t_c,
            "error_percent": None if t is None else 100 * (t - t_c) / t_c,
            "series": ([r["time"] for r in rows],
                       [average_axial_stress(r) for r in rows])})

    with open(output / "contact_gap.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["run_id", "method", "placement", "contact_time_s",
                         "theory_s", "error_percent"])
        for r in results:
            writer.writerow([r["run_id"], r["method"], r["placement"],
                             "" if r["contact_time"] is None else
                             f"{r['contact_time']:.6e}", f"{t_c:.6e}",
                             "" if r["error_percent"] is None else
                             f"{r['error_percent']:.2f}"])

    print(f"| method | placement | contact time (ms) | error vs t_c = "
          f"{1e3 * t_c:.3f} ms |")
    print("|---|---|---|---|")
    for r in results:
        if r["contact_time"] is None:
            print(f"| {r['method']} | {r['placement']} | none | - |")
        else:
            print(f"| {r['method']} | {r['placement']} | "
                  f"{1e3 * r['contact_time']:.3f} | "
                  f"{r['error_percent']:+.2f} % |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    placements = ["grid line", "mid cell"]
    figure, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for axis, placement in zip(axes, placements):
        for r in results:
            if r["placement"] != placement:
                continue
            times, stress = r["series"]
            axis.plot([1e3 * t for t in times], [-1e-6 * s for s in stress],
                      label=r["method"])
        axis.axvline(1e3 * t_c, color="k", linestyle=":", label="t_c")
        axis.set_xlim(0.8e3 * t_c, 1e3 * max(r["series"][0][-1]
                                             for r in results))
        axis.set_title(f"contact plane on a {placement}"
                       if placement == "grid line"
                       else "contact plane in mid cell")
        axis.set_xlabel("time (ms)")
        axis.grid(alpha=0.3)
    axes[0].set_ylabel("average axial stress, compression (MPa)")
    axes[1].legend()
    figure.tight_layout()
    figure.savefig(output / "contact_gap.png", dpi=120)
    print(f"written: {output / 'contact_gap.csv'}, "
          f"{output / 'contact_gap.png'}")


if __name__ == "__main__":
    main()
