#!/usr/bin/env python3
"""Percent error of multimaterial contact against the single-material run
in a compression study (seed 004 Fig. 5).

Reads a study made with fmpm_study.py from parameters/two_blocks_compression
.prm (its runs' history.csv): the average axial stress of the points
(sigma_yy, mass-weighted over the materials) against the axial strain
v t / H, and for each multimaterial run its percent difference from the
single-material run of the same particle update and mass matrix (the runs
labelled 'single ...'; LR-XPIC(5) against 'single XPIC(5)', and so on).

Writes ``compression_error.csv`` (per run: the largest |error| over strain
ranges) and ``compression_error.png`` (error against strain) into the
study's output directory and prints the table in Markdown.

Usage::

    compression_error.py STUDY_FILE [--output DIR] [--quick]
                         [--speed 0.962] [--height 0.1]
"""

import argparse
import csv
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fmpm_study  # noqa: E402
from contact_time import average_axial_stress, read_history  # noqa: E402


def reference_label(label):
    """The single-material run a multimaterial run is compared with."""
    for method in ("XPIC(5)", "FMPM(5)"):
        if method in label:
            return "single " + method
    return "single FLIP"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study")
    parser.add_argument("--output")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--speed", type=float, default=0.962)
    parser.add_argument("--height", type=float, default=0.1)
    args = parser.parse_args()

    study = fmpm_study.parse_study(Path(args.study), quick=args.quick)
    output = Path(args.output) if args.output else \
        fmpm_study.default_output_dir(args.study, args.quick)
    series = {}
    for run in fmpm_study.expand_runs(study, output):
        history = run.directory / "history.csv"
        if not history.exists():
            print(f"{run.run_id}: no history.csv (not run?)", file=sys.stderr)
            continue
        rows = read_history(history)
        label = run.swept.get("Label", run.label())
        series[label] = ([args.speed * r["time"] / args.height for r in rows],
                         [average_axial_stress(r) for r in rows])

    ranges = [(0.0, 0.05), (0.05, 0.10), (0.10, 0.15), (0.15, 0.21)]
    results = []
    for label, (strain, stress) in series.items():
        if label.startswith("single"):
            continue
        reference = series.get(reference_label(label))
        if reference is None:
            continue
        errors = []
        for s, a, b in zip(strain, stress, reference[1]):
            if s > 0.005 and b != 0:  # skip the first 0.5 % (tiny stresses)
                errors.append((s, 100 * (a - b) / b))
        worst = []
        for low, high in ranges:
            values = [abs(e) for s, e in errors if low <= s < high]
            worst.append(max(values) if values else None)
        results.append({"label": label, "errors": errors, "worst": worst,
                        "final_strain": strain[-1] if strain else None})

    with open(output / "compression_error.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["method", "reference"] + [
            f"max_abs_error_percent_{lo:.2f}_{hi:.2f}" for lo, hi in ranges])
        for r in results:
            writer.writerow([r["label"], reference_label(r["label"])] + [
                "" if w is None else f"{w:.4f}" for w in r["worst"]])

    print("| method | reference | " + " | ".join(
        f"max error, strain {100 * lo:.0f}-{100 * min(hi, 0.2):.0f} %"
        for lo, hi in ranges) + " |")
    print("|---|---|" + "---|" * len(ranges))
    for r in results:
        print(f"| {r['label']} | {reference_label(r['label'])} | " +
              " | ".join("-" if w is None else f"{w:.3f} %"
                         for w in r["worst"]) + " |")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    figure, axis = plt.subplots(figsize=(8, 4.5))
    for r in results:
        axis.plot([100 * s for s, _ in r["errors"]],
                  [e for _, e in r["errors"]], label=r["label"])
    axis.axhline(0, color="k", linewidth=0.5)
    axis.set_ylim(-15, 15)  # failed runs leave the frame
    axis.set_xlabel("axial strain (%)")
    axis.set_ylabel("average axial stress, % error against one material")
    axis.set_title("Two blocks in compression (seed 004 Fig. 5)")
    axis.grid(alpha=0.3)
    axis.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(output / "compression_error.png", dpi=120)
    print(f"written: {output / 'compression_error.csv'}, "
          f"{output / 'compression_error.png'}")


if __name__ == "__main__":
    main()
