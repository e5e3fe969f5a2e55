#!/usr/bin/env python3
"""Energy loss against the FMPM order of a study (contact_energy_order).

Reads ``results.csv`` of a study made with fmpm_study.py whose runs vary
``Mass matrix/Fmpm/Order`` and carry a ``Label``; the energy loss of a run
is 1 - final total energy / initial total energy, in percent. Writes
``energy_against_order.csv`` and ``energy_against_order.png`` (loss against
k, one line per label) into the study's output directory and prints the
table in Markdown. Failed runs show as "failed".

Usage::

    energy_against_order.py OUTPUT_DIR
"""

import argparse
import csv
import sys
from pathlib import Path

ORDER = "Mass matrix/Fmpm/Order"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output", type=Path,
                        help="the study's output directory (results.csv)")
    args = parser.parse_args()
    results = args.output / "results.csv"
    if not results.is_file():
        sys.exit(f"energy_against_order.py: no {results}; run the study first")
    with open(results, newline="") as stream:
        rows = list(csv.DictReader(stream))
    labels, orders, loss = [], [], {}
    for row in rows:
        label, k = row["Label"], int(row[ORDER])
        if label not in labels:
            labels.append(label)
        if k not in orders:
            orders.append(k)
        if row["status"] == "completed":
            initial = float(row["initial_total_energy"])
            final = float(row["final_total_energy"])
            loss[label, k] = 100.0 * (1.0 - final / initial)
        else:
            loss[label, k] = None
    orders.sort()

    with open(args.output / "energy_against_order.csv", "w",
              newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["k"] + [f"energy_loss_percent {label}"
                                 for label in labels])
        for k in orders:
            writer.writerow([k] + ["" if loss.get((label, k)) is None else
                                   f"{loss[label, k]:.4f}" for label in labels])

    print("| k | " + " | ".join(labels) + " |")
    print("|---|" + "---|" * len(labels))
    for k in orders:
        cells = ["failed" if loss.get((label, k)) is None else
                 f"{loss[label, k]:.2f} %" for label in labels]
        print(f"| {k} | " + " | ".join(cells) + " |")

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("energy_against_order.py: no matplotlib; chart skipped")
        return
    figure, axes = plt.subplots(figsize=(6, 4))
    for label in labels:
        ks = [k for k in orders if loss.get((label, k)) is not None]
        axes.plot(ks, [loss[label, k] for k in ks], marker="o", label=label)
    axes.set_xlabel("FMPM order k")
    axes.set_ylabel("energy loss at the end (%)")
    axes.axhline(0, color="grey", linewidth=0.5)
    axes.legend()
    axes.grid(True, alpha=0.3)
    figure.tight_layout()
    figure.savefig(args.output / "energy_against_order.png", dpi=120)
    print(f"written: {args.output / 'energy_against_order.csv'}, "
          f"{args.output / 'energy_against_order.png'}")


if __name__ == "__main__":
    main()
