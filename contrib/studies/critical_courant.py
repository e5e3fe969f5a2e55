#!/usr/bin/env python3
"""Measured critical Courant numbers of a stability study against the
predictions.

Reads a stability study made with fmpm_study.py (its results.csv; the study
has ``chart stability_x = Time/Courant number``), brackets each method's
critical Courant number between the largest stable and the smallest
unstable value (per panel, e.g. per strain update), and predicts it

* by the textbook leapfrog dispersion relation of a uniform 1D grid
  (mpm_dispersion.fe_critical_courant: 1 lumped, 0.775 FMPM(2), 0.61
  FMPM(5), 1/sqrt(3) consistent/full), and
* by the linearised fmpm step on a periodic grid of the same points per
  cell (mpm_dispersion.critical_courant), in 1D and in the strip one cell
  high with roller walls (modes that vary across the strip).

fmpm's Courant number C sets dt = C h / (c + |v|max); the predictions are
for nu = c dt / h and are converted with C = nu (c + v) / c (option
--point-speed, default 0.1 for the vibrating bar).

Writes ``critical_courant.csv`` and ``critical_courant.png`` into the
study's output directory.

Usage::

    critical_courant.py STUDY_FILE [--output DIR] [--quick]
                        [--wave-speed C] [--point-speed V]
"""

import argparse
import csv
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fmpm_study  # noqa: E402
from frequency_error import scheme_of  # noqa: E402


def measured_limits(study_path, output, quick):
    """(data, [(panel, label, row of the method, low, high)])."""
    study = fmpm_study.parse_study(study_path, quick=quick)
    runs = fmpm_study.expand_runs(study, output)
    rows = fmpm_study.collect_results(study, runs)
    data = fmpm_study.ChartData(study, rows)
    limits = fmpm_study.stability_limits(data)
    grouped = fmpm_study.stability_cells(data)
    if isinstance(grouped, str):
        raise ValueError(grouped)
    _, _, cells = grouped
    result = []
    for item in limits:
        example = next(runs[0] for (x, y), runs in
                       cells[item["panel"]].items() if y == item["y"])
        result.append((item["panel"], item["y"], example,
                       item["largest_stable"], item["smallest_unstable"]))
    return data, result


def predict(data, row):
    """Predicted critical nu: (FE leapfrog, MPM 1D, MPM strip)."""
    import mpm_dispersion
    ppc, scheme = scheme_of(data, row)
    mass = scheme["mass"]
    if scheme["update"] in ("pic", "fmpm", "xpic") and mass == "consistent":
        fe = None  # the transfer itself amplifies (see stability.md)
    else:
        fe = mpm_dispersion.fe_critical_courant(
            "consistent" if mass == "full" else mass, scheme["order"])
    model = [mpm_dispersion.critical_courant(geometry, ppc, high=2.0,
                                             **scheme)
             for geometry in ("1d", "strip")]
    return fe, model[0], model[1]


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Critical Courant numbers of a stability study against "
                    "the dispersion predictions.")
    parser.add_argument("study", help="the study file")
    parser.add_argument("--output", metavar="DIR", help="the study's "
                        "output directory (default as fmpm_study.py)")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--wave-speed", type=float, default=10.0)
    parser.add_argument("--point-speed", type=float, default=0.1,
                        help="largest point speed |v| in dt = C h/(c+|v|)")
    arguments = parser.parse_args(argv)
    output = (Path(arguments.output).resolve() if arguments.output else
              fmpm_study.default_output_dir(arguments.study, arguments.quick))
    data, limits = measured_limits(arguments.study, output, arguments.quick)
    factor = (arguments.wave_speed + arguments.point_speed) / \
        arguments.wave_speed
    table = []
    for panel, label, row, low, high in limits:
        fe, model_1d, model_strip = predict(data, row)

        def as_c(nu):
            return None if nu is None else nu * factor
        table.append({"panel": panel, "method": label, "stable": low,
                      "unstable": high, "fe": as_c(fe),
                      "model_1d": as_c(model_1d),
                      "model_strip": as_c(model_strip)})
        print(f"{panel:8s} {label:20s} measured [{low}, {high}]  FE "
              f"{'-' if fe is None else f'{fe * factor:.3f}'}  model 1D "
              f"{'-' if model_1d is None else f'{model_1d * factor:.3f}'}  "
              f"strip {'-' if model_strip is None else f'{model_strip * factor:.3f}'}",
              flush=True)
    with open(output / "critical_courant.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["panel", "method", "largest_stable_C",
                         "smallest_unstable_C", "fe_leapfrog_C",
                         "mpm_model_1d_C", "mpm_model_strip_C"])
        for item in table:
            writer.writerow([item["panel"], item["method"]] + [
                "" if item[k] is None else f"{item[k]:.4g}"
                for k in ("stable", "unstable", "fe", "model_1d",
                          "model_strip")])
    draw(output / "critical_courant.png", data, table)
    print(f"Written {output / 'critical_courant.csv'} and "
          f"{output / 'critical_courant.png'}")
    return 0


def draw(path, data, table):
    plt = fmpm_study.import_pyplot()
    if plt is None:
        return
    panels = list(dict.fromkeys(item["panel"] for item in table))
    methods = list(dict.fromkeys(item["method"] for item in table))
    fig, axes = plt.subplots(1, len(panels), squeeze=False, sharey=True,
                             figsize=(1.5 + 0.75 * len(methods) * len(panels)
                                      + 1.5, 5))
    tested = [x for item in table for x in (item["stable"], item["unstable"])
              if x is not None]
    top = max(tested) * 1.1
    for ax, panel in zip(axes[0], panels):
        items = [i for i in table if i["panel"] == panel]
        for x, item in enumerate(items):
            low = item["stable"] or 0.0
            if item["unstable"] is None:
                ax.annotate("", xy=(x, top), xytext=(x, low),
                            arrowprops=dict(arrowstyle="->", color="C0",
                                            lw=2))
            else:
                ax.bar([x], [item["unstable"] - low], bottom=[low],
                       width=0.6, color="C0", alpha=0.35,
                       label="measured (largest stable .. smallest "
                       "unstable)" if x == 0 else None)
            for key, offset, marker, colour, name in (
                    ("fe", 0.0, "_", "k", "FE leapfrog, uniform grid"),
                    ("model_1d", -0.15, "o", "C3",
                     "linearised fmpm step, 1D"),
                    ("model_strip", 0.15, "x", "C2",
                     "linearised fmpm step, strip")):
                value = item[key]
                if value is None:
                    continue
                shown = min(value, top)
                ax.plot([x + offset], [shown], marker=marker, color=colour,
                        markersize=22 if marker == "_" else 7,
                        markeredgewidth=2, linestyle="none",
                        label=name if x == 0 else None)
                if value > top:
                    ax.annotate(f"{value:.2f}", (x + offset, shown),
                                textcoords="offset points", xytext=(0, -14),
                                ha="center", fontsize=7, color=colour)
        ax.set_xticks(range(len(items)))
        ax.set_xticklabels([i["method"] for i in items], rotation=35,
                           ha="right")
        ax.set_title(f"strain update {panel}" if panel else "")
        ax.set_ylim(0, top * 1.02)
        ax.grid(True, axis="y", alpha=0.3)
    axes[0][0].set_ylabel("critical Courant number C (dt = C h/(c+|v|))")
    handles, labels = [], []
    for ax in axes[0]:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            if label not in labels:
                handles.append(handle)
                labels.append(label)
    fig.legend(handles, labels, loc="lower center", ncol=4, fontsize=8)
    fig.suptitle(f"{data.study.title}\ncritical Courant number: measured "
                 "and predicted (arrow: stable up to the largest value "
                 "tested)", fontsize=10)
    fig.tight_layout(rect=(0, 0.07, 1, 1))
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
