#!/usr/bin/env python3
"""The cantilever under gravity (parameters/cantilever.prm): tip deflection
against time for several settings, against a converged reference run.

Each run is fmpm on the scene with a fragment of settings, writing
particles_NNNNN.csv at every output. The tip deflection is the mean
vertical displacement of the points that start within 1/16 m of the free
end (x > 3.9375 m), the same strip at every cell size. The J field of the
last output (or of --j-time) is drawn for the runs named with --j-field.

Writes into the output directory: <run>/ (fmpm's output), tip_<run>.csv
(time, tip deflection), results.csv (one row per run: settings, status,
steps, wall time, tip RMS error against the reference up to the run's end
or failure, maximum checkerboard_j and its time, energy_error),
tip_deflection.png, and j_field.png.

Usage::

    cantilever.py [--output DIR] [--fmpm PATH] [--runs NAME ...]
                  [--reference NAME] [--plot-only]

The runs are the table RUNS below; --runs picks some by name.
"""

import argparse
import csv
import glob
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SCENE = ROOT / "parameters" / "cantilever.prm"

# name: (label, settings as (subsection path, parameter, value))
COMMON = []


def mesh(h):
    """Mesh settings for cell size h (m), the scene's box."""
    n = round(1 / h)
    return [("Mesh", "Subdivisions", f"{int(4.5 * n)}, {6 * n}")]


def flip(psi):
    return [("Particle update", "Model name", "flip"),
            ("Particle update/Flip", "Position update psi", str(psi))]


def courant(c):
    return [("Time", "Courant number", str(c))]


def strain_update(name):
    return [("Time", "Strain update", name)]


def shape(name):
    return [("Shape function", "Type", name)]


RUNS = {
    # The reference: h = 1/16, C = 0.1, psi = 1.
    "reference": ("reference h = 1/16, C = 0.1, psi = 1",
                  mesh(1 / 16) + courant(0.1) + flip(1)),
    "psi1_c0.1": ("FLIP psi = 1, C = 0.1", courant(0.1) + flip(1)),
    "psi1_c0.2_h16": ("FLIP psi = 1, C = 0.2, h = 1/16",
                      mesh(1 / 16) + courant(0.2) + flip(1)),
    "psi1_c0.4": ("FLIP psi = 1, C = 0.4", courant(0.4) + flip(1)),
    "psi0_c0.4": ("FLIP psi = 0, C = 0.4", courant(0.4) + flip(0)),
    "psi0_c0.2": ("FLIP psi = 0, C = 0.2", courant(0.2) + flip(0)),
    "psi0_c0.1": ("FLIP psi = 0, C = 0.1", courant(0.1) + flip(0)),
    "psi1_c0.8": ("FLIP psi = 1, C = 0.8", courant(0.8) + flip(1)),
    "psi1_c0.4_h16": ("FLIP psi = 1, C = 0.4, h = 1/16",
                      mesh(1 / 16) + courant(0.4) + flip(1)),
    "psi0_c0.4_h16": ("FLIP psi = 0, C = 0.4, h = 1/16",
                      mesh(1 / 16) + courant(0.4) + flip(0)),
    "psi1_c0.4_classic": ("FLIP psi = 1, C = 0.4, classic",
                          courant(0.4) + flip(1) + shape("classic")),
    "psi0_c0.1_classic": ("FLIP psi = 0, C = 0.1, classic",
                          courant(0.1) + flip(0) + shape("classic")),
    "psi1_c0.4_ugimp": ("FLIP psi = 1, C = 0.4, uGIMP",
                        courant(0.4) + flip(1) + shape("ugimp")),
    "psi1_c0.4_cpgimp": ("FLIP psi = 1, C = 0.4, cpGIMP",
                         courant(0.4) + flip(1) + shape("cpgimp")),
    # The position update against the strain update's velocity: USL- strains
    # a point with v+, which psi = 0 moves it with.
    "psi0_c0.4_usl": ("FLIP psi = 0, C = 0.4, USL-",
                      courant(0.4) + flip(0) + strain_update("usl")),
    "psi1_c0.4_usl": ("FLIP psi = 1, C = 0.4, USL-",
                      courant(0.4) + flip(1) + strain_update("usl")),
    "xpic2_c0.4": ("XPIC(2), C = 0.4",
                   courant(0.4) + [("Particle update", "Model name", "xpic"),
                                   ("Mass matrix", "Model name", "fmpm"),
                                   ("Mass matrix/Fmpm", "Order", "2")]),
    "fmpm2_c0.4": ("FMPM(2), C = 0.4",
                   courant(0.4) + [("Particle update", "Model name", "fmpm"),
                                   ("Mass matrix", "Model name", "fmpm"),
                                   ("Mass matrix/Fmpm", "Order", "2")]),
}

END_STRIP = 4 - 1 / 16


def fragment(settings, directory):
    """The prm text of settings plus the output settings."""
    lines = []
    for path, name, value in settings + [
            ("Output", "Directory", str(directory)),
            ("Output", "Write vtu", "false"),
            ("Output", "Write particle csv", "true")]:
        parts = path.split("/")
        lines += [f"subsection {p}" for p in parts]
        lines.append(f"  set {name} = {value}")
        lines += ["end"] * len(parts)
    return "\n".join(lines) + "\n"


def run(fmpm, name, output):
    directory = output / name
    directory.mkdir(parents=True, exist_ok=True)
    for old in glob.glob(str(directory / "particles_*.csv")):
        os.remove(old)
    override = directory / "override.prm"
    override.write_text(fragment(RUNS[name][1], directory.resolve()))
    start = time.time()
    with open(directory / "log.txt", "w") as log:
        subprocess.run([fmpm, str(SCENE), str(override)], stdout=log,
                       stderr=subprocess.STDOUT, cwd=str(ROOT / "parameters"))
    print(f"{name}: {time.time() - start:.1f} s", flush=True)


def read_csv(path):
    with open(path, newline="") as stream:
        return list(csv.DictReader(stream))


def tip_history(directory):
    """(times, deflections) from the particle csv files and history.csv."""
    files = sorted(glob.glob(str(directory / "particles_*.csv")))
    history = read_csv(directory / "history.csv")
    if not files:
        return [], []
    first = read_csv(files[0])
    strip = {row["id"]: float(row["y"]) for row in first
             if float(row["x"]) > END_STRIP}
    times, tips = [], []
    for index, path in enumerate(files):
        if index >= len(history):
            break
        rows = [row for row in read_csv(path) if row["id"] in strip]
        if not rows:
            break
        tips.append(sum(float(r["y"]) - strip[r["id"]] for r in rows)
                    / len(rows))
        times.append(float(history[index]["time"]))
    return times, tips


def interpolate(times, values, t):
    if t <= times[0]:
        return values[0]
    for i in range(1, len(times)):
        if times[i] >= t:
            w = (t - times[i - 1]) / (times[i] - times[i - 1])
            return (1 - w) * values[i - 1] + w * values[i]
    return values[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--output", default="study_cantilever")
    parser.add_argument("--fmpm",
                        default=str(ROOT / "build/applications/fmpm/fmpm"))
    parser.add_argument("--runs", nargs="*", default=list(RUNS))
    parser.add_argument("--reference", default="reference")
    parser.add_argument("--plot", nargs="*", default=[
        "psi1_c0.4", "psi0_c0.4", "psi0_c0.2", "psi0_c0.1"])
    parser.add_argument("--j-field", nargs="*", default=["psi0_c0.4",
                                                          "psi1_c0.4"])
    parser.add_argument("--j-time", type=float, default=2.0)
    parser.add_argument("--plot-only", action="store_true")
    args = parser.parse_args()
    output = Path(args.output).resolve()
    output.mkdir(parents=True, exist_ok=True)
    for name in args.runs:
        if name not in RUNS:
            sys.exit(f"unknown run <{name}>; known: {', '.join(RUNS)}")
    if not args.plot_only:
        for name in args.runs:
            run(args.fmpm, name, output)

    tips = {}
    for name in RUNS:
        directory = output / name
        if (directory / "history.csv").exists():
            tips[name] = tip_history(directory)
            with open(output / f"tip_{name}.csv", "w") as stream:
                stream.write("time,tip_deflection\n")
                for t, u in zip(*tips[name]):
                    stream.write(f"{t:.6g},{u:.6g}\n")

    reference = tips.get(args.reference)
    if reference is None and (HERE.parent.parent / "doc" / "studies" /
                              "cantilever" / "reference.csv").exists():
        # Without the reference run: the shipped reference curve.
        rows = read_csv(ROOT / "doc" / "studies" / "cantilever" /
                        "reference.csv")
        reference = ([float(r["time"]) for r in rows],
                     [float(r["tip_deflection"]) for r in rows])
    rows = []
    for name, (times, values) in tips.items():
        directory = output / name
        summary = json.loads((directory / "summary.json").read_text()) \
            if (directory / "summary.json").exists() else {}
        rms = ""
        if reference and name != args.reference and times:
            errors = [v - interpolate(*reference, t)
                      for t, v in zip(times, values)]
            rms = f"{math.sqrt(sum(e * e for e in errors) / len(errors)):.4f}"
        history = read_csv(directory / "history.csv")
        rows.append({
            "run": name, "label": RUNS[name][0],
            "status": summary.get("status", "no summary"),
            "end_time": summary.get("end_time", ""),
            "n_steps": summary.get("n_steps", ""),
            "wall_seconds": summary.get("wall_seconds", ""),
            "tip_rms_error": rms,
            "tip_min": f"{min(values):.4f}" if values else "",
            "tip_at_2.6": f"{interpolate(times, values, 2.6):.4f}"
            if values and times[-1] >= 2.6 else "",
            "max_checkerboard_j": summary.get("max_checkerboard_j", ""),
            "max_checkerboard_j_time":
                summary.get("max_checkerboard_j_time", ""),
            "checkerboard_j_at_1.5": next(
                (r["checkerboard_j"] for r in history
                 if float(r["time"]) >= 1.5 - 1e-9), ""),
            "energy_error": summary.get("energy_error", ""),
            "lost_points": summary.get("lost_points", ""),
        })
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
    figure, axes = plt.subplots(2, 1, figsize=(8, 7), sharex=True)
    if reference:
        axes[0].plot(*reference, "k-", lw=2.5, alpha=0.4,
                     label=RUNS[args.reference][0])
    for name in args.plot:
        if name in tips and tips[name][0]:
            axes[0].plot(*tips[name], label=RUNS[name][0])
            history = read_csv(output / name / "history.csv")
            axes[1].plot([float(r["time"]) for r in history],
                         [float(r["checkerboard_j"]) for r in history],
                         label=RUNS[name][0])
    axes[0].set_ylabel("tip deflection (m)")
    axes[0].legend(fontsize=8)
    axes[0].grid(alpha=0.3)
    axes[1].axhline(0.1, color="r", ls=":", label="warning threshold")
    axes[1].set_yscale("log")
    axes[1].set_ylabel("checkerboard_j")
    axes[1].set_xlabel("time (s)")
    axes[1].legend(fontsize=8)
    axes[1].grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(output / "tip_deflection.png", dpi=110)

    names = [n for n in args.j_field if (output / n / "history.csv").exists()]
    if names:
        figure, axes = plt.subplots(len(names), 1,
                                    figsize=(8, 3.6 * len(names)))
        axes = axes if len(names) > 1 else [axes]
        for axis, name in zip(axes, names):
            history = read_csv(output / name / "history.csv")
            files = sorted(glob.glob(str(output / name / "particles_*.csv")))
            index = min(range(min(len(files), len(history))),
                        key=lambda i: abs(float(history[i]["time"])
                                          - args.j_time))
            points = read_csv(files[index])
            image = axis.scatter([float(r["x"]) for r in points],
                                 [float(r["y"]) for r in points],
                                 c=[float(r["J"]) for r in points], s=3,
                                 cmap="coolwarm", vmin=0.8, vmax=1.2)
            axis.set_aspect("equal")
            axis.set_title(f"{RUNS[name][0]}: J at t = "
                           f"{float(history[index]['time']):.2f} s",
                           fontsize=9)
            figure.colorbar(image, ax=axis, label="J")
        figure.tight_layout()
        figure.savefig(output / "j_field.png", dpi=110)


if __name__ == "__main__":
    main()
