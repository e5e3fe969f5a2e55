#!/usr/bin/env python3
"""FLIP's position update against the strain update on the vibrating bar
(parameters/vibrating_bar.prm): the time-averaged L2 displacement and
velocity errors for Position update psi = 0 and 1, strain update USL- and
USAVG+, at Courant numbers 0.5 to 0.0625.

Writes into the output directory: <run>/ (fmpm's output), results.csv (one
row per run) and displacement_error.png.

Usage::

    position_update.py [--output DIR] [--fmpm PATH] [--plot-only]
"""

import argparse
import csv
import json
import subprocess
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SCENE = ROOT / "parameters" / "vibrating_bar.prm"
COURANT = [0.5, 0.25, 0.125, 0.0625]
CASES = [(psi, strain) for strain in ["usl", "usavg+"] for psi in [0, 1]]


def name(psi, strain, courant):
    return f"psi{psi}_{strain}_c{courant}"


def run(fmpm, output, psi, strain, courant):
    directory = output / name(psi, strain, courant)
    directory.mkdir(parents=True, exist_ok=True)
    override = directory / "override.prm"
    override.write_text(
        f"subsection Time\n  set Strain update = {strain}\n"
        f"  set Courant number = {courant}\nend\n"
        "subsection Particle update\n  subsection Flip\n"
        f"    set Position update psi = {psi}\n  end\nend\n"
        f"subsection Output\n  set Directory = {directory.resolve()}\nend\n")
    with open(directory / "log.txt", "w") as log:
        subprocess.run([fmpm, str(SCENE), str(override)], stdout=log,
                       stderr=subprocess.STDOUT, cwd=str(ROOT / "parameters"),
                       check=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", default="study_position_update")
    parser.add_argument("--fmpm",
                        default=str(ROOT / "build/applications/fmpm/fmpm"))
    parser.add_argument("--plot-only", action="store_true")
    args = parser.parse_args()
    output = Path(args.output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    rows = []
    for psi, strain in CASES:
        for courant in COURANT:
            if not args.plot_only:
                run(args.fmpm, output, psi, strain, courant)
            summary = json.loads(
                (output / name(psi, strain, courant) / "summary.json")
                .read_text())
            rows.append({"psi": psi, "strain_update": strain,
                         "courant": courant,
                         "n_steps": summary["n_steps"],
                         "error_displacement_l2":
                             f"{summary['error_displacement_l2']:.5g}",
                         "error_velocity_l2":
                             f"{summary['error_velocity_l2']:.5g}",
                         "energy_error": f"{summary['energy_error']:.3g}"})
    with open(output / "results.csv", "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print("| " + " | ".join(rows[0]) + " |")
    for row in rows:
        print("| " + " | ".join(str(v) for v in row.values()) + " |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axis = plt.subplots(figsize=(6.5, 4.5))
    for psi, strain in CASES:
        points = [(float(r["courant"]), float(r["error_displacement_l2"]))
                  for r in rows
                  if r["psi"] == psi and r["strain_update"] == strain]
        matches = (psi == 1) == (strain == "usavg+")
        axis.loglog(*zip(*points), "o-" if matches else "s--",
                    label=f"psi = {psi}, {strain.upper()}"
                    + (" (matching)" if matches else ""))
    c = COURANT
    axis.loglog(c, [0.04 * x for x in c], "k:", lw=1, label="first order")
    axis.set_xlabel("Courant number (time step)")
    axis.set_ylabel("displacement L2 error (time-averaged)")
    axis.set_title("vibrating bar, 48 cells: position vs strain update")
    axis.grid(alpha=0.3, which="both")
    axis.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(output / "displacement_error.png", dpi=110)


if __name__ == "__main__":
    main()
