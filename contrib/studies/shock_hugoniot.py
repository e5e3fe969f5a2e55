#!/usr/bin/env python3
"""Piston shocks of a study against the Rankine-Hugoniot jump conditions.

Reads a study made with fmpm_study.py from parameters/shock_nickel.prm
(parameters/studies/shock_hugoniot.study): every run's particles_NNNNN.csv
at t = 3, 4 and 5 us (outputs 3, 4, 5; their times from history.csv). The
piston speed u and the bar's right end come from the run's
``Boundary conditions/Moving wall 0/Function constants`` (``u=..., right=...``),
the method from its ``Label``.

- The front at each time is the smallest x of the points with vx < -u/2;
  the shock speed U_s is minus the slope of the least-squares line through
  the three front positions against time. The times are the outputs'
  (the first step at or after 3, 4, 5 us: up to one step late), not the
  nominal ones. This front moves in steps of the point spacing (0.125 mm
  in the scene: about 1 % of U_s over 2 us), so the CSV file also has U_s
  from a front interpolated between points: per row of points (equal
  initial y, from output 0) the x where -vx crosses u/2, averaged over the
  rows.
- The plateau at 5 us: the points with x between front + 3 mm and piston -
  3 mm (piston = right - u t). Its particle speed up = -mean(vx), its axial
  stress mean(stress_xx) and internal energy mean(internal_energy); the
  CSV file also has the standard deviation of stress_xx over the plateau
  in percent of its mean (ringing behind the front).
- U_s, sigma_xx and U are compared with the model's jump conditions
  (hugoniot.jump, material constants from the parameter files) at the
  measured up, since the jump conditions relate the states on both sides
  of the front; up itself is reported against u.

Writes ``shock_hugoniot.csv`` and ``shock_hugoniot.png`` (left: U_s against
up per method with the model's Hugoniot; right: the percent errors of U_s,
sigma_xx and U against u) into the study's output directory and prints the
table in Markdown. Runs without the three outputs (failed, not run) are
rows with their status and no numbers; a run that failed after them is
measured and marked with its status. Writes nothing when no run has the
outputs (e.g. after ``fmpm_study.py --prune``, which deletes them).

Usage::

    shock_hugoniot.py STUDY_FILE [--output DIR] [--quick]
"""

import argparse
import csv
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fmpm_study  # noqa: E402
import hugoniot  # noqa: E402

WALL = "Boundary conditions/Moving wall 0/Function constants"
MATERIAL = "Material 0/Mie gruneisen/"
#: hugoniot.jump argument -> (parameter, default of fmpm)
CONSTANTS = {"K": (MATERIAL + "Bulk modulus", 1.88e11),
             "G": (MATERIAL + "Shear modulus", 7.6e10),
             "gamma0": (MATERIAL + "Gruneisen gamma", 2.0),
             "S1": (MATERIAL + "S1", 1.44),
             "rho0": ("Material 0/Density", 8870.0)}
OUTPUTS = (3, 4, 5)       # the particles_NNNNN.csv used; the last: plateau
MARGIN = 3e-3             # plateau: this far from the front and the piston
QUANTITIES = (("Us", "U_s"), ("sigma", "sigma_xx"), ("U", "U"))
GOALS = {"Us": 1.0, "sigma": 1.0, "U": 2.0}   # percent


def constants_of(text):
    """The ``name=value`` pairs of a Function constants string."""
    return {name.strip(): float(value) for name, value in
            re.findall(r"([A-Za-z_]\w*)\s*=\s*([^,]+)", text)}


def output_times(directory, count):
    """Times of the outputs from history.csv (one row per output)."""
    try:
        with open(directory / "history.csv", newline="") as stream:
            times = [float(row["time"]) for row in csv.DictReader(stream)]
    except (OSError, KeyError, ValueError):
        return None
    return times if len(times) >= count else None


def read_points(path):
    points = np.genfromtxt(path, delimiter=",", names=True)
    return points if points.size else None


def run_status(directory):
    try:
        summary = json.loads((directory / "summary.json").read_text())
    except (OSError, ValueError):
        try:
            record = json.loads((directory / "run.json").read_text())
            return str(record.get("status", "not run"))
        except (OSError, ValueError):
            return "not run"
    status = str(summary.get("status", "unknown"))
    if summary.get("failure_time") is not None:
        status += f" at t = {1e6 * float(summary['failure_time']):.3g} us"
    return status


def interpolated_front(points, rows, u):
    """Mean over the rows of points of the x where -vx crosses u/2,
    interpolated linearly between the two points on either side; None when
    no row has a crossing."""
    crossings = []
    for row in np.unique(rows):
        x, v = points["x"][rows == row], -points["vx"][rows == row]
        order = np.argsort(x)
        x, v = x[order], v[order]
        first = np.argmax(v > 0.5 * u)
        if first == 0 or v[first] <= 0.5 * u:
            continue
        x0, x1, v0, v1 = x[first - 1], x[first], v[first - 1], v[first]
        crossings.append(x0 + (0.5 * u - v0) * (x1 - x0) / (v1 - v0))
    return np.mean(crossings) if crossings else None


def measure(directory, u, right):
    """(up, U_s, sigma, U, plateau spread of sigma in %, U_s from the
    interpolated front or None) or a reason."""
    files = {int(p.stem.split("_")[-1]): p
             for p in directory.glob("particles_*.csv")}
    missing = [n for n in OUTPUTS if n not in files]
    if missing:
        return f"no output {missing[0]}"
    times = output_times(directory, max(OUTPUTS) + 1)
    if times is None:
        return "no history.csv with the output times"
    # rows of points (equal initial y) for the interpolated front; the
    # files list the points by id
    rows = None
    if 0 in files:
        start = read_points(files[0])
        if start is not None:
            rows = np.unique(np.round(start["y"], 9), return_inverse=True)[1]
    fronts, t, smooth = [], [], []
    for n in OUTPUTS:
        points = read_points(files[n])
        if points is None:
            return f"output {n} empty"
        behind = points["vx"] < -0.5 * u
        if not behind.any():
            return f"no shocked point at output {n}"
        fronts.append(points["x"][behind].min())
        if rows is not None and len(rows) == len(points) and \
                all(f is not None for f in smooth):
            smooth.append(interpolated_front(points, rows, u))
        else:
            smooth.append(None)
        t.append(times[n])
    Us = -np.polyfit(t, fronts, 1)[0]
    piston = right - u * t[-1]
    plateau = (points["x"] > fronts[-1] + MARGIN) & \
        (points["x"] < piston - MARGIN)
    if plateau.sum() == 0:
        return "no points between front and piston"
    up = -points["vx"][plateau].mean()
    sigma = points["stress_xx"][plateau]
    U = points["internal_energy"][plateau].mean()
    values = (up, Us, sigma.mean(), U,
              100 * sigma.std() / abs(sigma.mean()))
    if not all(math.isfinite(v) for v in values):
        return "not finite"
    Us_smooth = -np.polyfit(t, smooth, 1)[0] \
        if all(f is not None for f in smooth) else None
    return values + (Us_smooth,)


def percent(value, exact):
    return 100.0 * (value / exact - 1.0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("study")
    parser.add_argument("--output")
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()

    study = fmpm_study.parse_study(Path(args.study), quick=args.quick)
    output = Path(args.output) if args.output else \
        fmpm_study.default_output_dir(args.study, args.quick)
    base = fmpm_study.read_prm(study.base)

    rows = []
    for run in fmpm_study.expand_runs(study, output):
        settings = dict(base, **run.settings)
        wall = constants_of(settings.get(WALL, ""))
        u, right = wall.get("u"), wall.get("right")
        material = {name: float(settings.get(path, default))
                    for name, (path, default) in CONSTANTS.items()}
        row = {"run": run.run_id,
               "method": run.swept.get("Label", settings.get(
                   "Particle update/Model name", "?")),
               "u": u, "status": run_status(run.directory)}
        result = measure(run.directory, u, right) \
            if u is not None and right is not None else "no u or right"
        if isinstance(result, str):
            row["note"] = result
            rows.append(row)
            continue
        up, Us, sigma, U, spread, Us_smooth = result
        Us_rh, sigma_rh, J_rh, U_rh = hugoniot.jump(up, **material)
        row.update(up=up, up_error=percent(up, u), Us=Us, Us_rh=Us_rh,
                   Us_error=percent(Us, Us_rh), sigma=sigma,
                   sigma_rh=sigma_rh, sigma_error=percent(sigma, sigma_rh),
                   U=U, U_rh=U_rh, U_error=percent(U, U_rh), spread=spread,
                   Us_smooth=Us_smooth, note="",
                   Us_smooth_error=None if Us_smooth is None else
                   percent(Us_smooth, Us_rh))
        rows.append(row)

    if not any("up" in r for r in rows):
        sys.exit(f"shock_hugoniot.py: no run in {output} has the particle "
                 "outputs 3, 4, 5 (not run yet, or pruned: run the analysis "
                 "before fmpm_study.py --prune); nothing written")

    columns = [("run", "run", None), ("method", "method", None),
               ("u", "u_m_per_s", "{:.6g}"),
               ("up", "up_measured_m_per_s", "{:.6g}"),
               ("up_error", "up_against_u_percent", "{:.4f}"),
               ("Us", "Us_m_per_s", "{:.6g}"),
               ("Us_rh", "Us_RH_m_per_s", "{:.6g}"),
               ("Us_error", "Us_error_percent", "{:.4f}"),
               ("sigma", "sigma_xx_Pa", "{:.6g}"),
               ("sigma_rh", "sigma_xx_RH_Pa", "{:.6g}"),
               ("sigma_error", "sigma_xx_error_percent", "{:.4f}"),
               ("U", "U_J_per_kg", "{:.6g}"),
               ("U_rh", "U_RH_J_per_kg", "{:.6g}"),
               ("U_error", "U_error_percent", "{:.4f}"),
               ("spread", "sigma_xx_plateau_std_percent", "{:.3g}"),
               ("Us_smooth", "Us_interpolated_front_m_per_s", "{:.6g}"),
               ("Us_smooth_error", "Us_interpolated_front_error_percent",
                "{:.4f}"),
               ("status", "status", None), ("note", "note", None)]
    with open(output / "shock_hugoniot.csv", "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow([header for _, header, _ in columns])
        for r in rows:
            writer.writerow([
                "" if r.get(key) is None else
                (form.format(r[key]) if form else r[key])
                for key, _, form in columns])

    print("| method | u (m/s) | up (m/s) | up vs u | U_s (m/s) | U_s RH | "
          "error | σ_xx (GPa) | σ_xx RH | error | U (kJ/kg) | U RH | error |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        method = r["method"]
        if not str(r["status"]).startswith("completed"):
            method += f" ({r['status']})"
        head = f"| {method} | {r['u']:.0f} |"
        if r.get("up") is None:
            print(head + f" {r['note']} |" + " |" * 10)
            continue
        print(head + f" {r['up']:.1f} | {r['up_error']:+.2f} % "
              f"| {r['Us']:.0f} | {r['Us_rh']:.0f} | {r['Us_error']:+.2f} % "
              f"| {-1e-9 * r['sigma']:.3f} | {-1e-9 * r['sigma_rh']:.3f} "
              f"| {r['sigma_error']:+.2f} % "
              f"| {1e-3 * r['U']:.2f} | {1e-3 * r['U_rh']:.2f} "
              f"| {r['U_error']:+.2f} % |")
    failed = [r for r in rows if not str(r["status"]).startswith("completed")
              or r.get("up") is None]
    for r in failed:
        print(f"{r['run']} {r['method']} u = {r['u']}: {r['status']}"
              + (f" ({r['note']})" if r.get("note") else ""))

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("shock_hugoniot.py: no matplotlib; chart skipped")
        return
    material = {name: float(base.get(path, default))
                for name, (path, default) in CONSTANTS.items()}
    methods = list(dict.fromkeys(r["method"] for r in rows))
    markers = "osD^vP*X"
    figure, (hug, err) = plt.subplots(1, 2, figsize=(12, 4.6))
    ups = np.linspace(1.0, 2000.0, 200)
    hug.plot(ups, [hugoniot.jump(v, **material)[0] for v in ups], "k-",
             linewidth=1, label="jump conditions of the model")
    C0 = math.sqrt(material["K"] / material["rho0"])
    hug.plot(ups, C0 + material["S1"] * ups, "k:", linewidth=1,
             label=f"C0 + S1 up (C0 = {C0:.0f} m/s)")
    for i, method in enumerate(methods):
        done = [r for r in rows if r["method"] == method and "up" in r]
        hug.plot([r["up"] for r in done], [r["Us"] for r in done],
                 linestyle="none", marker=markers[i % len(markers)],
                 markerfacecolor="none", markersize=7 + 2 * (i % 2),
                 label=method)
    hug.set_xlabel("particle speed behind the front up (m/s)")
    hug.set_ylabel("shock speed U_s (m/s)")
    hug.set_xlim(0, 2000)
    hug.legend(fontsize=8)
    hug.grid(alpha=0.3)
    hug.set_title("U_s against up")

    limit = 5.0
    speeds = sorted({r["u"] for r in rows if r["u"] is not None})
    width = 0.6 * (min(np.diff(speeds)) if len(speeds) > 1 else 100.0)
    colors = {"Us": "C0", "sigma": "C1", "U": "C2"}
    for i, method in enumerate(methods):
        shift = width * ((i + 0.5) / max(len(methods), 1) - 0.5)
        done = [r for r in rows if r["method"] == method and "up" in r]
        for key, _ in QUANTITIES:
            x = np.array([r["u"] + shift for r in done])
            y = np.array([r[f"{key}_error"] for r in done])
            inside = np.abs(y) <= limit
            err.plot(x[inside], y[inside], linestyle="none",
                     marker=markers[i % len(markers)], color=colors[key],
                     markerfacecolor="none")
            for xo, yo in zip(x[~inside], y[~inside]):
                err.annotate(f"{yo:+.3g} %", (xo, np.sign(yo) * limit),
                             xytext=(0, -12 if yo > 0 else 6),
                             textcoords="offset points", fontsize=6,
                             ha="center", color=colors[key])
                err.plot([xo], [np.sign(yo) * limit * 0.97], linestyle="none",
                         marker="^" if yo > 0 else "v", color=colors[key])
    for goal, style in ((1.0, "--"), (2.0, ":")):
        err.axhline(goal, color="k", linewidth=0.6, linestyle=style)
        err.axhline(-goal, color="k", linewidth=0.6, linestyle=style)
    err.axhline(0, color="grey", linewidth=0.5)
    err.set_ylim(-limit, limit)
    err.set_xticks(speeds)
    err.set_xlabel("piston speed u (m/s); methods side by side")
    err.set_ylabel("error against the jump conditions (%)")
    err.set_title("U_s (blue), sigma_xx (orange), U (green); goals 1 %, 2 %")
    handles = [plt.Line2D([], [], linestyle="none", color="k",
                          markerfacecolor="none",
                          marker=markers[i % len(markers)], label=method)
               for i, method in enumerate(methods)]
    err.legend(handles=handles, fontsize=8)
    err.grid(alpha=0.3)
    figure.tight_layout()
    figure.savefig(output / "shock_hugoniot.png", dpi=120)
    print(f"written: {output / 'shock_hugoniot.csv'}, "
          f"{output / 'shock_hugoniot.png'}")


if __name__ == "__main__":
    main()
