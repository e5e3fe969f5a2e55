#!/usr/bin/env python3
"""Interpenetration, average axial stress and cost of the ellipse
compaction study (seed 004 Fig. 6).

Reads a study made with fmpm_study.py from parameters/ellipse_compaction.prm
(every run's particles_NNNNN.csv, history.csv and summary.json; run the
study without --prune, which deletes the particle files) and computes per
run:

(a) the points inside another body. A point counts when at least
    ``--votes`` (6) of its ``--neighbours`` (8) nearest other points belong
    to one single other body. A point on a clean interface has about half
    of its neighbours in its own body (the points beside and behind it), a
    point that has entered another ellipse is surrounded by that ellipse's
    points. The count of the initial state (particles_00000.csv, ellipses
    at least one cell apart) must be 0 and is reported as a check. The
    count is evaluated at every output, so its growth against compression
    is charted too.
(b) the average axial stress against compression v t / H: the mass-weighted
    average over the materials of history.csv's volume-averaged
    stress_yy_material_N (as contrib/studies/compression_error.py), and the
    piston's force per width, -reaction_wall0_y / W (the box-average stress
    the piston applies, voids included); both compressive positive, in GPa.
    "Final" values are the last output (75 %) and, less noisy, the mean
    over the outputs past 72.5 %.
(c) the volume ratio sum_p J_p V_p0 / (W (H - v t)): the points' current
    volumes (J from F) over the compressed box. Where bodies do not overlap
    it cannot exceed 1 (voids make it smaller), so its excess over 1 is a
    lower bound of the area in which bodies (or points of one body) overlap,
    in fractions of the box. V_p0 is the square of the initial point
    spacing (the median nearest-neighbour distance of the initial state).
    Also the points on the piston face (above it or less than 0.1 initial
    point spacings below it): a box wall pushes points that would enter it
    back onto its face, where they pile up in a line.
(d) wall time, steps, particle-steps per second and LR fits from
    summary.json, the share of the LR normals and point clouds in the wall
    time, and the wall time to reach the common compression (below) from
    the progress lines of log.txt, each over the DF run's.

Runs that fail stop at different compressions, so (a)-(d) are also given
at the largest output compression every run reached ("common").

Writes into the study's output directory ``ellipse_compaction.csv`` (one
row per run), ``ellipse_compaction_history.csv`` (per run and output:
compression, both stresses, points inside another body, contact nodes),
``ellipse_compaction.png`` (stress, interpenetration and volume ratio
against compression), ``ellipse_compaction_final.png`` (the initial state
and each run's last state, points coloured by body, the points inside
another body ringed) and ``ellipse_compaction_common.png`` (the same at the
common compression), and prints the tables in Markdown.

``--run LABEL DIR`` (repeated) analyses single fmpm output directories
instead of a study's runs (the checks on doc/studies/ellipse_compaction.md),
``--name`` changes the stem of the files written.

Usage::

    ellipse_compaction.py STUDY_FILE [--output DIR] [--quick]
    ellipse_compaction.py --run LABEL DIR [--run LABEL DIR ...] --output DIR
                          [--name STEM] [--title TEXT]
                          [--speed 100] [--height 0.002] [--width 0.001]
                          [--neighbours 8] [--votes 6]
"""

import argparse
import csv
import re
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

try:
    import numpy as np
except ImportError:  # pyenv's python3: use Debian's python3-numpy
    sys.path.append("/usr/lib/python3/dist-packages")
    import numpy as np

import fmpm_study  # noqa: E402
from contact_time import average_axial_stress, read_history  # noqa: E402


def read_points(path):
    """Columns of a particles_NNNNN.csv as a dict of arrays."""
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


def nearest_neighbours(xy, k):
    """Indices of the k nearest other points of every point."""
    try:
        from scipy.spatial import cKDTree
        _, index = cKDTree(xy).query(xy, k=k + 1)
        return index[:, 1:]
    except ImportError:
        result = np.empty((len(xy), k), dtype=int)
        for start in range(0, len(xy), 512):
            block = xy[start:start + 512]
            d2 = ((block[:, None, :] - xy[None, :, :]) ** 2).sum(axis=2)
            result[start:start + 512] = np.argsort(d2, axis=1)[:, 1:k + 1]
        return result


def inside_other_body(points, k=8, votes=6):
    """Boolean mask: the point has at least ``votes`` of its ``k`` nearest
    neighbours in one single other body."""
    body = points["body"].astype(int)
    neighbour_body = body[nearest_neighbours(
        np.stack([points["x"], points["y"]], axis=1), k)]
    inside = np.zeros(len(body), dtype=bool)
    for other in np.unique(body):
        count = ((neighbour_body == other) & (body[:, None] != other)).sum(
            axis=1)
        inside |= count >= votes
    return inside


def progress(path):
    """(time, wall seconds) of fmpm's progress lines in a run's log.txt."""
    pattern = re.compile(r"^\*\*\* Step\s+\d+\s+t =\s*(\S+).*wall\s+(\S+) s")
    pairs = [(0.0, 0.0)]
    try:
        with open(path, errors="replace") as stream:
            for line in stream:
                match = pattern.match(line)
                if match:
                    pairs.append((float(match.group(1)),
                                  float(match.group(2))))
    except OSError:
        return None
    return pairs if len(pairs) > 1 else None


def wall_at(pairs, time):
    """Wall seconds at simulated time ``time`` (linear between progress
    lines), or None when the log does not reach it."""
    if not pairs or pairs[-1][0] < time - 1e-15:
        return None
    for (t0, w0), (t1, w1) in zip(pairs, pairs[1:]):
        if t1 >= time:
            return w0 + (w1 - w0) * (time - t0) / (t1 - t0) if t1 > t0 \
                else w1
    return pairs[-1][1]


def point_spacing(points):
    """Median nearest-neighbour distance (the initial lattice spacing)."""
    xy = np.stack([points["x"], points["y"]], axis=1)
    neighbour = nearest_neighbours(xy, 1)[:, 0]
    return float(np.median(np.linalg.norm(xy - xy[neighbour], axis=1)))


def body_colours(n):
    """Distinct colours for n bodies, neighbours in numbering far apart in
    the colour map."""
    import matplotlib
    cmap = matplotlib.colormaps["tab20"]
    step = 7 if n > 7 else 1
    return [cmap(((i * step) % 20) / 19.999) for i in range(n)]


def draw_states(pyplot, panels, args, path):
    """The first panel (the initial state: left, tall) and the others (a
    grid of two columns, enlarged twice as seed 004 Fig. 6 B, C), points
    coloured by body, points inside another body ringed in black. A panel
    is (title, points, mask, piston height in m)."""
    from matplotlib.gridspec import GridSpec
    colours = body_colours(int(panels[0][1]["body"].max()) + 1)
    others = len(panels) - 1
    rows = max(1, (others + 1) // 2)
    figure = pyplot.figure(figsize=(2.6 + 2 * 4.6, 0.6 + 2.5 * rows))
    grid = GridSpec(rows, 3, figure=figure, width_ratios=[1, 2, 2])
    axes = [figure.add_subplot(grid[:, 0])] + [
        figure.add_subplot(grid[i // 2, 1 + i % 2]) for i in range(others)]
    width = 1e3 * args.width
    for number, (axis, (title, points, mask, top)) in enumerate(
            zip(axes, panels)):
        body = points["body"].astype(int)
        x, y = 1e3 * points["x"], 1e3 * points["y"]
        axis.scatter(x, y, s=1.2 if number == 0 else 2.0,
                     c=[colours[b] for b in body], marker="s",
                     linewidths=0)
        if mask.any():
            axis.scatter(x[mask], y[mask], s=7, facecolors="none",
                         edgecolors="k", linewidths=0.4)
        top *= 1e3
        axis.plot([0, 0, width, width], [top, 0, 0, top], color="k",
                  linewidth=0.8)
        axis.plot([0, width], [top, top], color="0.4", linewidth=2)
        axis.set_aspect("equal")
        axis.set_xlim(-0.02, width + 0.02)
        axis.set_ylim(-0.02, top + 0.02)
        axis.set_title(title, fontsize=9)
        axis.tick_params(labelsize=7)
        axis.set_xlabel("x (mm)", fontsize=8)
        axis.set_ylabel("y (mm)", fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=130)
    pyplot.close(figure)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study", nargs="?")
    parser.add_argument("--run", nargs=2, action="append",
                        metavar=("LABEL", "DIR"),
                        help="analyse this fmpm output directory instead of "
                        "a study's runs (repeatable; needs --output)")
    parser.add_argument("--name", default="ellipse_compaction",
                        help="stem of the files written")
    parser.add_argument("--title", help="chart title (default: the "
                        "study's)")
    parser.add_argument("--output")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--speed", type=float, default=100.0)
    parser.add_argument("--height", type=float, default=0.002)
    parser.add_argument("--width", type=float, default=0.001)
    parser.add_argument("--neighbours", type=int, default=8)
    parser.add_argument("--votes", type=int, default=6)
    args = parser.parse_args()

    if args.run:
        if not args.output:
            parser.error("--run needs --output")
        output = Path(args.output)
        output.mkdir(parents=True, exist_ok=True)
        runs = [(label, f"run {label}", Path(directory))
                for label, directory in args.run]
        title = args.title or "Ellipse compaction"
    elif args.study:
        study = fmpm_study.parse_study(Path(args.study), quick=args.quick)
        output = Path(args.output) if args.output else \
            fmpm_study.default_output_dir(args.study, args.quick)
        runs = [(run.swept.get("Label", run.label()), run.run_id,
                 run.directory)
                for run in fmpm_study.expand_runs(study, output)]
        title = args.title or study.title
    else:
        parser.error("give a study file or --run LABEL DIR")
    stem = args.name

    results, histories, snapshots = [], {}, {}
    for label, run_id, directory in runs:
        summary = fmpm_study.read_json(directory / "summary.json") or {}
        history_path = directory / "history.csv"
        if not history_path.exists():
            print(f"{run_id}: no history.csv (not run?)", file=sys.stderr)
            continue
        rows = read_history(history_path)
        files = sorted(directory.glob("particles_*.csv"))
        if not files:
            print(f"{run_id}: no particles_*.csv (pruned?)",
                  file=sys.stderr)
        series = []
        snapshots[label] = []
        spacing = None
        for index, row in enumerate(rows):
            counted = ratio = on_piston = None
            top = args.height - args.speed * row["time"]
            if index < len(files):
                points = read_points(files[index])
                mask = inside_other_body(points, args.neighbours, args.votes)
                counted = int(mask.sum())
                if index == 0:
                    spacing = point_spacing(points)
                snapshots[label].append(
                    ({k: points[k] for k in ("x", "y", "body")}, mask))
                ratio = (points["J"].sum() * spacing ** 2
                         / (args.width * top))
                on_piston = int((points["y"] >= top - 0.1 * spacing).sum())
            series.append({
                "time": row["time"],
                "compression": 100 * args.speed * row["time"] / args.height,
                "stress": -1e-9 * average_axial_stress(row),
                "piston": -1e-9 * row.get("reaction_wall0_y", float("nan"))
                / args.width,
                "inside": counted,
                "volume_ratio": ratio,
                "on_piston": on_piston,
                "contact_nodes": row.get("contact_nodes")})
        histories[label] = series
        walls = progress(directory / "log.txt")
        phases = summary.get("phase_wall_seconds", {})
        last = series[-1]
        tail = [s for s in series if s["compression"] >= 72.5 - 1e-9]
        inside = [s["inside"] for s in series if s["inside"] is not None]
        contact = [s["contact_nodes"] for s in series
                   if s["contact_nodes"] is not None]
        results.append({
            "label": label,
            "run": run_id,
            "status": summary.get("status", "not run"),
            "final_compression_percent": last["compression"],
            "final_stress_gpa": last["stress"],
            "final_piston_stress_gpa": last["piston"],
            "stress_mean_72_75_gpa": (np.mean([s["stress"] for s in tail])
                                      if tail else None),
            "piston_mean_72_75_gpa": (np.mean([s["piston"] for s in tail])
                                      if tail else None),
            "inside_initial": inside[0] if inside else None,
            "inside_final": inside[-1] if inside else None,
            "inside_max": max(inside) if inside else None,
            "volume_ratio_final": last["volume_ratio"],
            "volume_ratio_max": max((s["volume_ratio"] for s in series
                                     if s["volume_ratio"] is not None),
                                    default=None),
            "points_on_piston_final": last["on_piston"],
            "n_particles": summary.get("n_particles"),
            "contact_nodes_mean": np.mean(contact) if contact else None,
            "n_steps": summary.get("n_steps"),
            "wall_seconds": summary.get("wall_seconds"),
            "particle_steps_per_second":
                summary.get("particle_steps_per_second"),
            "logistic_regression_fits":
                summary.get("logistic_regression_fits"),
            "lr_share": ((phases.get("contact: normals", 0)
                          + phases.get("contact: point clouds", 0))
                         / summary["wall_seconds"]
                         if summary.get("wall_seconds") else None),
            "progress": walls,
        })

    # the largest output compression every run reached
    common = min((s[-1]["compression"] for s in histories.values()),
                 default=None)
    for r in results:
        series = histories[r["label"]]
        index = max(i for i, s in enumerate(series)
                    if s["compression"] <= common + 1e-9)
        r["common_index"] = index
        r["common_compression_percent"] = series[index]["compression"]
        r["stress_at_common_gpa"] = series[index]["stress"]
        r["piston_at_common_gpa"] = series[index]["piston"]
        r["inside_at_common"] = series[index]["inside"]
        r["volume_ratio_at_common"] = series[index]["volume_ratio"]
        r["wall_to_common_s"] = wall_at(r.pop("progress"),
                                        series[index]["time"])
    by_label = {r["label"]: r for r in results}
    df = by_label.get("DF")
    lr = by_label.get("LR")
    for r in results:
        r["wall_over_df"] = (r["wall_seconds"] / df["wall_seconds"]
                             if df and df["wall_seconds"] and r["wall_seconds"]
                             else None)
        r["stress_over_lr"] = (r["final_stress_gpa"] / lr["final_stress_gpa"]
                               if lr and lr["final_stress_gpa"] else None)
        r["wall_to_common_over_df"] = (
            r["wall_to_common_s"] / df["wall_to_common_s"]
            if df and df["wall_to_common_s"] and r["wall_to_common_s"]
            else None)
        r["stress_at_common_over_lr"] = (
            r["stress_at_common_gpa"] / lr["stress_at_common_gpa"]
            if lr and lr["stress_at_common_gpa"] else None)

    columns = ["label", "run", "status", "final_compression_percent",
               "final_stress_gpa", "final_piston_stress_gpa",
               "stress_mean_72_75_gpa", "piston_mean_72_75_gpa",
               "stress_over_lr", "inside_initial", "inside_final",
               "inside_max", "volume_ratio_final", "volume_ratio_max",
               "points_on_piston_final", "n_particles", "contact_nodes_mean", "n_steps",
               "wall_seconds", "wall_over_df", "particle_steps_per_second",
               "logistic_regression_fits", "common_compression_percent",
               "stress_at_common_gpa", "piston_at_common_gpa",
               "stress_at_common_over_lr", "inside_at_common",
               "volume_ratio_at_common", "wall_to_common_s",
               "wall_to_common_over_df", "lr_share"]

    def text(value):
        if value is None:
            return ""
        if isinstance(value, (float, np.floating)):
            return f"{value:.5g}"
        return str(value)

    with open(output / f"{stem}.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(columns)
        for r in results:
            writer.writerow([text(r[c]) for c in columns])
    with open(output / f"{stem}_history.csv", "w",
              newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow(["label", "time", "compression_percent",
                         "average_stress_yy_gpa", "piston_stress_gpa",
                         "points_inside_other_body", "volume_ratio",
                         "points_on_piston", "contact_nodes"])
        for label, series in histories.items():
            for s in series:
                writer.writerow([label, text(s["time"]),
                                 text(s["compression"]), text(s["stress"]),
                                 text(s["piston"]), text(s["inside"]),
                                 text(s["volume_ratio"]),
                                 text(s["on_piston"]),
                                 text(s["contact_nodes"])])

    print("| method | status | compression | average -sigma_yy (GPa) | "
          "mean 72.5-75 % | piston (GPa) | / LR | points inside another "
          "body: start / end / max | volume ratio, end | points on the "
          "piston | steps | wall (s) | / DF | particle-steps/s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    def cell(r, key, fmt):
        """A table cell: the value formatted, '-' where there is none."""
        return "-" if r[key] is None else format(r[key], fmt)

    for r in results:
        def f(key, fmt):
            return cell(r, key, fmt)
        print(f"| {r['label']} | {r['status']} | "
              f"{f('final_compression_percent', '.1f')} % | "
              f"{f('final_stress_gpa', '.1f')} | "
              f"{f('stress_mean_72_75_gpa', '.1f')} | "
              f"{f('final_piston_stress_gpa', '.1f')} | "
              f"{f('stress_over_lr', '.3f')} | "
              f"{f('inside_initial', 'd')} / {f('inside_final', 'd')} / "
              f"{f('inside_max', 'd')} of {f('n_particles', 'd')} | "
              f"{f('volume_ratio_final', '.3f')} | "
              f"{f('points_on_piston_final', 'd')} | "
              f"{f('n_steps', 'd')} | {f('wall_seconds', '.0f')} | "
              f"{f('wall_over_df', '.2f')} | "
              f"{f('particle_steps_per_second', '.3g')} |")

    if results:
        print()
        print(f"At {results[0]['common_compression_percent']:.1f} % "
              f"compression (the largest output every run reached):")
        print()
        print("| method | average -sigma_yy (GPa) | / LR | piston (GPa) | "
              "points inside another body | volume ratio | wall time to "
              "here (s) | / DF |")
        print("|---|---|---|---|---|---|---|---|")
        for r in results:
            def g(key, fmt):
                return cell(r, key, fmt)
            print(f"| {r['label']} | {g('stress_at_common_gpa', '.2f')} | "
                  f"{g('stress_at_common_over_lr', '.3f')} | "
                  f"{g('piston_at_common_gpa', '.2f')} | "
                  f"{g('inside_at_common', 'd')} | "
                  f"{g('volume_ratio_at_common', '.3f')} | "
                  f"{g('wall_to_common_s', '.0f')} | "
                  f"{g('wall_to_common_over_df', '.2f')} |")

    pyplot = fmpm_study.import_pyplot()
    if pyplot is None:
        print("matplotlib missing: no charts", file=sys.stderr)
        return
    figure, (stress_axis, inside_axis, volume_axis) = pyplot.subplots(
        1, 3, figsize=(15, 4.4))
    for index, (label, series) in enumerate(histories.items()):
        colour = f"C{index}"
        c = [s["compression"] for s in series]
        stress_axis.plot(c, [s["stress"] for s in series], color=colour,
                         label=f"{label}: points")
        stress_axis.plot(c, [s["piston"] for s in series], color=colour,
                         linestyle=":", linewidth=1,
                         label=f"{label}: piston force / width")
        counted = [(s["compression"], s["inside"]) for s in series
                   if s["inside"] is not None]
        inside_axis.plot([a for a, _ in counted], [b for _, b in counted],
                         color=colour, label=label, marker=".")
        ratios = [(s["compression"], s["volume_ratio"]) for s in series
                  if s["volume_ratio"] is not None]
        volume_axis.plot([a for a, _ in ratios], [b for _, b in ratios],
                         color=colour, label=label)
    stress_axis.set_xlabel("compression v t / H (%)")
    stress_axis.set_ylabel("average axial stress -sigma_yy (GPa)")
    stress_axis.set_title("axial stress")
    stress_axis.grid(alpha=0.3)
    stress_axis.legend(fontsize=7)
    inside_axis.set_xlabel("compression v t / H (%)")
    inside_axis.set_ylabel(f"points inside another body "
                           f"({args.votes} of {args.neighbours} neighbours)")
    inside_axis.set_title("interpenetration")
    inside_axis.grid(alpha=0.3)
    inside_axis.legend(fontsize=8)
    volume_axis.axhline(1, color="k", linewidth=0.6)
    volume_axis.set_xlabel("compression v t / H (%)")
    volume_axis.set_ylabel("sum of point volumes J V0 / box area")
    volume_axis.set_title("volume ratio (above 1: overlap)")
    volume_axis.grid(alpha=0.3)
    volume_axis.legend(fontsize=8)
    figure.suptitle(title)
    figure.tight_layout()
    figure.savefig(output / f"{stem}.png", dpi=120)

    labels = [label for label in histories if snapshots[label]]
    if labels:
        points, mask = snapshots[labels[0]][0]
        initial = ("initial", points, mask, args.height)

        def panel(label, index):
            series = histories[label][index]
            points, mask = snapshots[label][index]
            return (f"{label}, {series['compression']:.0f} %: "
                    f"{int(mask.sum())} points inside another body",
                    points, mask,
                    args.height - args.speed * series["time"])

        draw_states(pyplot, [initial] + [
            panel(label, len(snapshots[label]) - 1) for label in labels],
            args, output / f"{stem}_final.png")
        draw_states(pyplot, [initial] + [
            panel(r["label"], r["common_index"]) for r in results
            if r["label"] in labels and
            r["common_index"] < len(snapshots[r["label"]])],
            args, output / f"{stem}_common.png")
    print("written: " + ", ".join(
        str(output / f"{stem}{suffix}") for suffix in (
            ".csv", "_history.csv", ".png", "_final.png", "_common.png")))


if __name__ == "__main__":
    main()
