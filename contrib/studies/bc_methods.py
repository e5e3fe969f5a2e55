#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""Compare the velocity boundary-condition methods of seed 000 Sec. 2.4.

Runs parameters/piston.prm (a bar compressed by a piston, fixed at x = 0,
rollers on its sides) once per method and mass matrix, and draws
doc/studies/bc_methods.png: the largest velocity-condition error
|v+ . n - v_b| over the run (summary.json) and the error of the fixed end's
reaction force against the quasi-static elastic force E H u(t) / L
(history.csv, mean over t >= 0.15 s) against the wall time of the run.
Writes the numbers to bc_methods.csv and prints a Markdown table.

    contrib/studies/bc_methods.py [--fmpm PATH] [--output DIR] [--quick]
"""

import argparse
import csv
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
METHODS = ["constrained", "lumped", "velocity", "unlumped 1", "unlumped 2",
           "collection full", "collection partial"]
MASS_MATRICES = [("full", "full", ""),
                 ("FMPM(3)", "fmpm", "subsection Fmpm\n  set Order = 3\n end"),
                 ("lumped", "lumped", "")]
# The scene's constants (parameters/piston.prm).
E, H, L, V0, T0 = 1e4, 0.125, 1.0, 0.01, 0.1


def import_pyplot():
    try:
        import matplotlib
    except ImportError:
        sys.path.append("/usr/lib/python3/dist-packages")
        import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    return pyplot


def reaction_error(history_file):
    rows = list(csv.DictReader(open(history_file)))
    measured = expected = 0.0
    for row in rows:
        t = float(row["time"])
        if t >= 0.15:
            measured += float(row["reaction_0_x"])
            expected += E * H * V0 * (t - T0 / 2) / L
    return abs(measured / expected - 1) if expected > 0 else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmpm", default=str(ROOT / "build/applications/fmpm/fmpm"))
    parser.add_argument("--output", default="study_bc_methods")
    parser.add_argument("--chart", default=str(ROOT / "doc/studies/bc_methods.png"))
    parser.add_argument("--quick", action="store_true",
                        help="end at t = 0.16 s instead of 0.2 s")
    args = parser.parse_args()
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    end_time = 0.16 if args.quick else 0.2

    results = []
    runs = [(m, label, name, extra) for label, name, extra in MASS_MATRICES
            for m in METHODS]
    for index, (method, label, name, extra) in enumerate(runs):
        directory = out / f"{name}_{method.replace(' ', '_')}"
        override = (f"subsection Mass matrix\n set Model name = {name}\n {extra}\nend\n"
                    f"subsection Boundary conditions\n set Method = {method}\nend\n"
                    f"subsection Time\n set End time = {end_time}\nend\n"
                    f"subsection Output\n set Directory = {directory}\nend\n"
                    "subsection Timer\n set Type = none\nend\n")
        directory.mkdir(parents=True, exist_ok=True)
        (directory / "override.prm").write_text(override)
        start = time.time()
        process = subprocess.run([args.fmpm, str(ROOT / "parameters/piston.prm"),
                                  str(directory / "override.prm")],
                                 capture_output=True, text=True)
        summary = json.loads((directory / "summary.json").read_text())
        status = summary.get("status", "missing")
        ok = status == "completed"
        row = {"mass_matrix": label, "method": method, "status": status,
               "wall_seconds": summary.get("wall_seconds", time.time() - start),
               "velocity_condition_error": summary.get("velocity_condition_error"),
               "reaction_error": reaction_error(directory / "history.csv") if ok else None}
        results.append(row)
        print(f"[{index + 1}/{len(runs)}] {label:8s} {method:18s} {status[:40]:40s} "
              f"wall {row['wall_seconds']:.2f} s", flush=True)

    with open(out / "bc_methods.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(results[0].keys()))
        writer.writeheader()
        writer.writerows(results)

    print("\n| mass matrix | method | status | wall s | max BC error / v0 | reaction error |")
    print("| --- | --- | --- | --- | --- | --- |")
    for r in results:
        bc = r["velocity_condition_error"]
        re = r["reaction_error"]
        print(f"| {r['mass_matrix']} | {r['method']} | {r['status'][:30]} | "
              f"{r['wall_seconds']:.2f} | "
              f"{'-' if bc is None else f'{bc / V0:.2e}'} | "
              f"{'-' if re is None else f'{100 * re:.2f} %'} |")

    pyplot = import_pyplot()
    figure, axes = pyplot.subplots(1, 2, figsize=(12, 5))
    markers = dict(zip(METHODS, "osD^v<>"))
    colours = {"full": "tab:blue", "FMPM(3)": "tab:orange", "lumped": "tab:green"}
    for r in results:
        failed = r["status"] != "completed"
        for axis, key, scale in ((axes[0], "velocity_condition_error", 1 / V0),
                                 (axes[1], "reaction_error", 100)):
            value = r[key]
            if failed or value is None:
                value, face = (1e1 if key == "velocity_condition_error" else 1e2) / scale * scale, "none"
                axis.scatter(r["wall_seconds"], value, marker="x", color=colours[r["mass_matrix"]])
                continue
            axis.scatter(r["wall_seconds"], max(value * scale, 1e-12),
                         marker=markers[r["method"]], color=colours[r["mass_matrix"]],
                         label=f"{r['mass_matrix']}, {r['method']}")
    axes[0].set_ylabel("largest |v+ . n - v_b| / v0 on condition nodes")
    axes[1].set_ylabel("fixed-end reaction error vs E H u / L  [%]")
    for axis in axes:
        axis.set_xscale("log")
        axis.set_yscale("log")
        axis.set_xlabel("wall time of the run [s]")
        axis.grid(True, which="both", alpha=0.3)
    axes[0].set_title("Velocity-condition error (x: run failed)")
    axes[1].set_title("Reaction-force error (x: run failed)")
    handles, labels = axes[1].get_legend_handles_labels()
    figure.legend(handles, labels, loc="lower center", ncol=4, fontsize=7)
    figure.suptitle("Piston (parameters/piston.prm): velocity BC methods of seed 000 Sec. 2.4")
    figure.tight_layout(rect=(0, 0.16, 1, 0.95))
    Path(args.chart).parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(args.chart, dpi=110)
    print(f"\nchart: {args.chart}")


if __name__ == "__main__":
    main()
