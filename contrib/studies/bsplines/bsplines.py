#!/usr/bin/env python3
"""B-spline shape functions and the mass matrix in 2D: convergence and
critical Courant numbers (doc/studies/bsplines.md).

Two bars in a strip one cell high with roller walls on y = 0 and y = H:

* ``vbar``: fmpm's vibrating bar (parameters/vibrating_bar.prm): L = 1,
  held at x = 0, free at x = L, mesh [0, 1.5]; period 0.4 s;
* ``tielen``: Tielen's bar (E = 100, rho = 1, L = 25, both ends fixed;
  Tielen et al., Procedia Eng. 175 (2017) 265), mesh [0, 25]; period 5 s.

Each run: one period of the first mode, v0 = 1e-6 (linear regime), USAVG+,
the relative L2 velocity error against the mode averaged over 40 outputs
(summary.json error_velocity_l2). Swept: n = 8 ... 128 cells in the bar;
classic, ugimp, b2spline, b3spline ((p + 1)^2 points per cell); lumped FLIP,
FMPM(2, 4, 8, 16), XPIC(5) and the full mass with the FMPM update
(CG to 1e-13, no weak nodes); points on the Gauss points of each knot span
(a body mesh whose cells are the knot spans) or uniformly spaced
('Points per cell'); a fixed tiny time step (Courant 0.02 at 64 cells) or
Courant 0.2 / 0.5.

``run`` executes the runs in priority order (tiers), appends one CSV row a
run to results.csv and skips runs already there (resumable);
``critical`` bisects the critical Courant number of each method (energy
doubles, or |energy error| > 1 %, within 20 periods of the vibrating bar,
32 cells); ``plot`` draws the charts and writes orders.csv.

Usage::

    bsplines.py run [--tiers 1,2,3] [--fmpm PATH] [--output DIR]
    bsplines.py critical [--fmpm PATH] [--output DIR]
    bsplines.py plot [--output DIR]
"""

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent.parent
BASE = REPO / "parameters" / "vibrating_bar.prm"
DEFAULT_OUTPUT = REPO / "doc" / "studies" / "bsplines"

SHAPES = {"classic": 1, "ugimp": 1, "b2spline": 2, "b3spline": 3}
METHODS = ["FLIP", "FMPM(2)", "FMPM(4)", "FMPM(8)", "FMPM(16)", "XPIC(5)",
           "exact"]
RESOLUTIONS = [8, 16, 32, 64, 128]
V0 = 1e-6
FIELDS = ["scene", "shape", "placement", "step", "method", "cells", "h",
          "dt", "courant", "status", "n_steps", "n_particles",
          "error_velocity_l2", "error_displacement_l2", "energy_error",
          "wall_seconds", "particle_steps_per_second"]


class Scene:
    """The geometry and mode of one bar."""

    def __init__(self, name):
        self.name = name
        if name == "vbar":
            self.length, self.mesh_length = 1.0, 1.5
            self.beta = math.pi / 2.0
            self.rollers = "0, 2, 3"
        else:
            self.length, self.mesh_length = 25.0, 25.0
            self.beta = math.pi / 25.0
            self.rollers = "0, 1, 2, 3"
        self.wave_speed = 10.0
        self.omega = self.beta * self.wave_speed
        self.period = 2.0 * math.pi / self.omega

    def h(self, cells):
        return self.length / cells

    def mesh_cells(self, cells):
        return int(round(self.mesh_length / self.h(cells)))


def knots_in_bar(scene, cells, degree):
    """The x coordinates that split the bar [0, L] into pieces inside one
    knot span of the open-knot basis each (knots at the vertices for
    p = 1, 3, at the cell midpoints for p = 2, clamped to the mesh)."""
    h = scene.h(cells)
    n_mesh = scene.mesh_cells(cells)
    if degree == 2:
        knots = [0.0] + [(i + 0.5) * h for i in range(n_mesh)] + \
            [n_mesh * h]
    else:
        knots = [i * h for i in range(n_mesh + 1)]
    inside = sorted({min(k, scene.length) for k in knots
                     if k <= scene.length + 1e-12 * h})
    if inside[-1] < scene.length - 1e-12 * h:
        inside.append(scene.length)
    return inside


def write_body_mesh(path, scene, cells, degree):
    """A UCD mesh of the bar [0, L] x [0, h] with one cell per knot span."""
    xs = knots_in_bar(scene, cells, degree)
    h = scene.h(cells)
    nx = len(xs)
    with open(path, "w") as out:
        out.write(f"{2 * nx} {nx - 1} 0 0 0\n")
        for j, y in enumerate((0.0, h)):
            for i, x in enumerate(xs):
                out.write(f"{j * nx + i + 1} {x!r} {y!r} 0\n")
        for i in range(nx - 1):
            out.write(f"{i + 1} 0 quad {i + 1} {i + 2} {nx + i + 2} "
                      f"{nx + i + 1}\n")


def method_settings(method):
    if method == "FLIP":
        return [("Particle update", "Model name", "flip"),
                ("Mass matrix", "Model name", "lumped")]
    if method.startswith("exact"):
        # 'exact': the default weak-node remedy (nodes with m~_ii < 0.1 m_i
        # take the lumped velocity: the free end's outer vertices);
        # 'exact, all nodes': none.
        threshold = "0" if method == "exact, all nodes" else "0.1"
        return [("Particle update", "Model name", "fmpm"),
                ("Mass matrix", "Model name", "full"),
                ("Mass matrix/Full", "Tolerance", "1e-13"),
                ("Mass matrix/Full", "Weak node threshold", threshold),
                ("Mass matrix/Full", "Maximum iterations", "10000")]
    update = "xpic" if method.startswith("XPIC") else "fmpm"
    order = method[method.index("(") + 1:-1]
    return [("Particle update", "Model name", update),
            ("Mass matrix", "Model name", "fmpm"),
            ("Mass matrix/Fmpm", "Order", order)]


def override_text(settings):
    """deal.II parameter text of [(subsection path, name, value)]."""
    lines = []
    for section, name, value in settings:
        parts = [s for s in section.split("/") if s]
        for part in parts:
            lines.append(f"subsection {part}")
        lines.append(f"  set {name} = {value}")
        lines.extend(["end"] * len(parts))
    return "\n".join(lines) + "\n"


def run_settings(scene, shape, placement, cells, method, time_settings,
                 end_time, workdir):
    degree = SHAPES[shape]
    h = scene.h(cells)
    s = [("Mesh", "Subdivisions", f"{scene.mesh_cells(cells)}, 1"),
         ("Mesh", "Upper corner", f"{scene.mesh_length!r}, {h!r}"),
         ("Boundary conditions", "Roller boundary ids", scene.rollers),
         ("Shape function", "Type", shape),
         ("Body 0", "Points per cell", str(degree + 1 if degree > 1
                                            else 2)),
         ("Body 0", "Function constants", f"v0={V0!r}, beta={scene.beta!r}"),
         ("Reference solution", "Function constants",
          f"v0={V0!r}, beta={scene.beta!r}, omega={scene.omega!r}"),
         ("Time", "Strain update", "usavg+"),
         ("Time", "Courant number limit", "none"),
         ("Time", "Check stability limit", "false"),
         ("Time", "End time", repr(end_time)),
         ("Output", "Interval", repr(scene.period / 40.0)),
         ("Output", "Write vtu", "false"),
         ("Output", "Directory", str(workdir / "out"))]
    if placement == "gauss":
        mesh = workdir / "bar.inp"
        write_body_mesh(mesh, scene, cells, degree)
        s += [("Body 0", "Shape", "mesh"), ("Body 0", "File name", str(mesh))]
    else:
        s += [("Body 0", "Center", f"{scene.length / 2!r}, {h / 2!r}"),
              ("Body 0", "Half lengths", f"{scene.length / 2!r}, {h / 2!r}")]
    s += time_settings
    s += method_settings(method)
    return s


def run_fmpm(fmpm, settings, workdir):
    """Runs fmpm; returns summary.json as a dict (status 'failed: ...'
    without one)."""
    prm = workdir / "override.prm"
    prm.write_text(override_text(settings))
    with open(workdir / "log.txt", "w") as log:
        code = subprocess.call(["nice", "-n", "10", fmpm, str(BASE),
                                str(prm)], stdout=log,
                               stderr=subprocess.STDOUT, cwd=workdir)
    summary_path = workdir / "out" / "summary.json"
    if summary_path.exists():
        return json.loads(summary_path.read_text())
    tail = (workdir / "log.txt").read_text().strip().splitlines()[-3:]
    return {"status": f"failed (exit {code}): " + " | ".join(tail)}


def tiny_time_step(scene):
    """Courant 0.02 at 64 cells in the bar, the same dt at every n."""
    return 0.02 * scene.h(64) / scene.wave_speed


def planned_runs(tiers):
    """(tier, scene, shape, placement, step, method, cells) in priority
    order."""
    plan = []

    def add(tier, scenes, shapes, placements, steps, cells_list,
            methods=METHODS):
        if tier not in tiers:
            return
        for scene in scenes:
            for step in steps:
                for placement in placements:
                    for shape in shapes:
                        if shape == "ugimp" and placement == "gauss":
                            continue
                        for cells in cells_list:
                            for method in methods:
                                plan.append((tier, scene, shape, placement,
                                             step, method, cells))

    both = ["vbar", "tielen"]
    add(1, both, ["b2spline", "classic", "b3spline"], ["gauss"], ["tiny"],
        RESOLUTIONS[:4])
    add(1, both, ["ugimp"], ["uniform"], ["tiny"], RESOLUTIONS[:4])
    add(2, both, ["b2spline", "classic", "b3spline"], ["gauss"], ["0.2"],
        RESOLUTIONS)
    add(2, both, ["ugimp"], ["uniform"], ["0.2"], RESOLUTIONS)
    add(6, ["vbar"], ["b2spline", "b3spline"], ["gauss"], ["tiny", "0.2"],
        RESOLUTIONS[:4], ["exact, all nodes"])
    add(3, both, ["b2spline", "classic"], ["uniform"], ["tiny", "0.2"],
        RESOLUTIONS[:4])
    add(4, both, ["b2spline", "classic"], ["gauss"], ["0.5"],
        RESOLUTIONS[:4])
    add(7, both, ["b3spline"], ["uniform"], ["tiny", "0.2"],
        RESOLUTIONS[:4])
    add(5, both, ["b2spline", "classic", "b3spline"], ["gauss"], ["tiny"],
        RESOLUTIONS[4:])
    return plan


def key_of(row):
    return (row["scene"], row["shape"], row["placement"], row["step"],
            row["method"], str(row["cells"]))


def read_rows(path):
    if not path.exists():
        return []
    with open(path) as f:
        return list(csv.DictReader(f))


def command_run(args):
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    results = output / "results.csv"
    done = {key_of(r) for r in read_rows(results)}
    tiers = {int(t) for t in args.tiers.split(",")}
    plan = [p for p in planned_runs(tiers)
            if (p[1], p[2], p[3], p[4], p[5], str(p[6])) not in done]
    print(f"{len(plan)} runs to do ({len(done)} already in {results})",
          flush=True)
    new_file = not results.exists()
    with open(results, "a", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=FIELDS)
        if new_file:
            writer.writeheader()
        start = time.time()
        for index, (tier, scene_name, shape, placement, step, method,
                    cells) in enumerate(plan):
            scene = Scene(scene_name)
            if step == "tiny":
                dt = tiny_time_step(scene)
                time_settings = [("Time", "Time step", repr(dt))]
                courant = dt * scene.wave_speed / scene.h(cells)
            else:
                courant = float(step)
                dt = courant * scene.h(cells) / scene.wave_speed
                time_settings = [("Time", "Courant number", step)]
            with tempfile.TemporaryDirectory(prefix="bsplines_") as tmp:
                workdir = Path(tmp)
                summary = run_fmpm(args.fmpm,
                                   run_settings(scene, shape, placement,
                                                cells, method,
                                                time_settings,
                                                scene.period, workdir),
                                   workdir)
            row = {"scene": scene_name, "shape": shape,
                   "placement": placement, "step": step, "method": method,
                   "cells": cells, "h": scene.h(cells), "dt": dt,
                   "courant": courant,
                   "status": summary.get("status", "")}
            for name in FIELDS[10:]:
                row[name] = summary.get(name, "")
            writer.writerow(row)
            f.flush()
            print(f"[{index + 1}/{len(plan)}, {time.time() - start:.0f} s] "
                  f"tier {tier} {scene_name} {shape} {placement} dt={step} "
                  f"{method} n={cells}: {row['status']} error "
                  f"{row['error_velocity_l2']}", flush=True)


def is_unstable(summary):
    if not str(summary.get("status", "")).startswith("completed"):
        return True
    energy = summary.get("energy_error")
    return energy is None or not abs(float(energy)) < 0.01


def command_critical(args):
    """Bisection of the critical Courant number, vibrating bar, 32 cells,
    20 periods, v0 = 1e-3, uniform points."""
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    results = output / "critical_courant.csv"
    done = {(r["shape"], r["method"]) for r in read_rows(results)}
    fields = ["shape", "method", "largest_stable", "smallest_unstable",
              "runs"]
    new_file = not results.exists()
    scene = Scene("vbar")
    global V0
    V0 = 1e-3
    with open(results, "a", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        if new_file:
            writer.writeheader()
        for shape in ["b2spline", "b3spline", "classic"]:
            for method in METHODS:
                if (shape, method) in done:
                    continue
                low, high, runs = 0.05, 2.0, 0
                while high - low > 0.02:
                    courant = 0.5 * (low + high)
                    with tempfile.TemporaryDirectory(
                            prefix="bsplines_") as tmp:
                        workdir = Path(tmp)
                        settings = run_settings(
                            scene, shape, "uniform", 32, method,
                            [("Time", "Courant number", repr(courant)),
                             ("Reference solution", "Enable", "false"),
                             ("Failure detection", "Energy growth limit",
                              "2")],
                            20 * scene.period, workdir)
                        summary = run_fmpm(args.fmpm, settings, workdir)
                    runs += 1
                    if is_unstable(summary):
                        high = courant
                    else:
                        low = courant
                    print(f"critical {shape} {method}: C = {courant:.3f} "
                          f"{'unstable' if is_unstable(summary) else 'stable'}"
                          f" -> [{low:.3f}, {high:.3f}]", flush=True)
                writer.writerow({"shape": shape, "method": method,
                                 "largest_stable": f"{low:.3f}",
                                 "smallest_unstable": f"{high:.3f}",
                                 "runs": runs})
                f.flush()


def fitted_order(points):
    """Least-squares slope of -log(error) against log(n)."""
    pts = [(math.log(n), math.log(e)) for n, e in points if e > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in pts)
    return -sxy / sxx


def command_plot(args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    output = Path(args.output)
    rows = [r for r in read_rows(output / "results.csv")
            if r["status"].startswith("completed") and r["error_velocity_l2"]]
    curves = {}
    for r in rows:
        key = (r["scene"], r["step"], r["placement"], r["shape"],
               r["method"])
        curves.setdefault(key, []).append((int(r["cells"]),
                                           float(r["error_velocity_l2"])))
    with open(output / "orders.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["scene", "step", "placement", "shape", "method",
                         "order"] + [f"error_{n}" for n in RESOLUTIONS])
        for key in sorted(curves):
            pts = sorted(curves[key])
            by_n = dict(pts)
            writer.writerow(list(key) + [f"{fitted_order(pts):.2f}"] +
                            [f"{by_n[n]:.3e}" if n in by_n else ""
                             for n in RESOLUTIONS])
    styles = {"FLIP": "o-", "FMPM(2)": "v--", "FMPM(4)": "^--",
              "FMPM(8)": "<--", "FMPM(16)": ">--", "XPIC(5)": "x:",
              "exact": "s-", "exact, all nodes": "D-"}
    titles = {"vbar": "vibrating bar (held-free)",
              "tielen": "Tielen's bar (fixed-fixed)"}
    for step in ["tiny", "0.2", "0.5"]:
        for placement in ["gauss", "uniform"]:
            present = [k for k in curves if k[1] == step and k[2] == placement]
            if not present:
                continue
            fig, axes = plt.subplots(2, 4, figsize=(16, 7.5), sharex=True,
                                     sharey=True)
            for i, scene in enumerate(["vbar", "tielen"]):
                for j, shape in enumerate(SHAPES):
                    ax = axes[i][j]
                    # uGIMP: uniform points only (its domains tile the
                    # body only with uniform points).
                    points = "uniform" if shape == "ugimp" else placement
                    for method in METHODS + ["exact, all nodes"]:
                        pts = sorted(curves.get(
                            (scene, step, points, shape, method), []))
                        if pts:
                            ax.loglog([p[0] for p in pts],
                                      [p[1] for p in pts], styles[method],
                                      label=method, ms=4)
                    ax.set_title(f"{titles[scene]}: {shape}"
                                 + (" (uniform points)"
                                    if points != placement else ""),
                                 fontsize=9)
                    ax.set_xticks(RESOLUTIONS, [str(n) for n in RESOLUTIONS])
                    ax.xaxis.set_minor_formatter(
                        matplotlib.ticker.NullFormatter())
                    ax.grid(True, which="both", alpha=0.3)
                    if i == 1:
                        ax.set_xlabel("cells in the bar")
                    if j == 0:
                        ax.set_ylabel("velocity error (L2, time average)")
            axes[0][2].legend(fontsize=7)
            label = ("tiny time step (Courant 0.02 at 64 cells)"
                     if step == "tiny" else f"Courant {step}")
            fig.suptitle(f"B-splines and the mass matrix: {label}, "
                         f"{placement} points")
            fig.tight_layout()
            name = f"error_{'tiny' if step == 'tiny' else 'courant_' + step}"
            fig.savefig(output / f"{name}_{placement}.png", dpi=90)
            plt.close(fig)
            print(f"wrote {name}_{placement}.png")
    critical = read_rows(output / "critical_courant.csv")
    if critical:
        fig, ax = plt.subplots(figsize=(8, 4.5))
        shapes = ["classic", "b2spline", "b3spline"]
        for i, shape in enumerate(shapes):
            rows = {r["method"]: r for r in critical if r["shape"] == shape}
            xs = [j + (i - 1) * 0.25 for j in range(len(METHODS))]
            low = [float(rows[m]["largest_stable"]) if m in rows else
                   float("nan") for m in METHODS]
            high = [float(rows[m]["smallest_unstable"]) if m in rows else
                    float("nan") for m in METHODS]
            ax.bar(xs, high, width=0.25, label=shape, alpha=0.8)
            ax.plot(xs, low, "k_", ms=8)
        ax.set_xticks(range(len(METHODS)),
                      [m.replace("exact", "full (exact)") for m in METHODS])
        ax.set_ylabel("critical Courant number")
        ax.set_title("Vibrating bar, 32 cells, 20 periods: bars end at the "
                     "smallest unstable C\n(FLIP with B-splines: stable up "
                     "to 2, the largest tried)", fontsize=9)
        ax.legend()
        ax.grid(True, axis="y", alpha=0.3)
        fig.tight_layout()
        fig.savefig(output / "critical_courant.png", dpi=90)
        plt.close(fig)
        print("wrote critical_courant.png")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("command", choices=["run", "critical", "plot"])
    parser.add_argument("--tiers", default="1,2,6,3,4,7,5")
    parser.add_argument("--fmpm", default=str(REPO / "build" / "applications"
                                              / "fmpm" / "fmpm"))
    parser.add_argument("--output", default=str(DEFAULT_OUTPUT))
    args = parser.parse_args()
    {"run": command_run, "critical": command_critical,
     "plot": command_plot}[args.command](args)


if __name__ == "__main__":
    main()
