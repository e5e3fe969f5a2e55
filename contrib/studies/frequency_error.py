#!/usr/bin/env python3
"""Frequency error of the vibrating bar runs of a study.

Reads the runs of a study made with fmpm_study.py (results.csv and every
run's history.csv), measures each run's vibration frequency from the zero
crossings of the total momentum momentum_x(t) (cubic interpolation through
the four history rows around each sign change; the period is twice the mean
spacing of the crossings, which a damping exp(-gamma t) does not shift) and
compares the relative frequency error omega_h/omega - 1 with

* the textbook uniform-grid predictions, theta = pi h / (2 L), nu = c dt/h:
  lumped mass -theta^2 (1 - nu^2)/24, consistent mass
  +theta^2 (1 + nu^2)/24;
* the linearised fmpm step of each run's method (mpm_dispersion.py: the
  particle and strain updates and the particle mass matrices of fmpm on a
  periodic grid), which also predicts the energy left after the run (the
  damping of PIC-like updates).

Writes ``frequency_error.csv`` and ``frequency_error.png`` (the error
divided by theta^2 against h: the predictions are horizontal lines) into
the study's output directory.

Usage::

    frequency_error.py STUDY_FILE [--output DIR] [--quick]
                       [--wave-speed C] [--length L]

The defaults fit parameters/vibrating_bar.prm (c = 10 m/s, L = 1 m).
"""

import argparse
import csv
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import fmpm_study  # noqa: E402

#: fmpm's defaults of the parameters the linear model needs.
DEFAULTS = {
    "Particle update/Model name": "flip",
    "Mass matrix/Model name": "lumped",
    "Mass matrix/Fmpm/Order": "2",
    "Time/Strain update": "usavg+",
    "Time/Strain update mass matrix": "same",
    "Particle update/Flip pic blend/FLIP fraction": "0.95",
    "Body 0/Points per cell": "2",
}

#: Particle updates whose velocity update (all the linear model sees) is
#: that of another one.
SAME_VELOCITY_UPDATE = {"fmpm0": "flip", "flip midpoint": "flip",
                        "flip end velocity": "flip", "pic midpoint": "pic"}


def read_series(path):
    """(times, momentum_x, dts, total energies) of a history.csv, or None."""
    try:
        with open(path, newline="") as stream:
            rows = list(csv.DictReader(stream))
    except OSError:
        return None
    series = ([], [], [], [])
    for row in rows:
        values = [fmpm_study.to_float(row.get(k)) for k in
                  ("time", "momentum_x", "dt", "total_energy")]
        if None in values:
            continue
        for column, value in zip(series, values):
            column.append(value)
    return series if series[0] else None


def _lagrange(ts, ys, t):
    total = 0.0
    for i, (ti, yi) in enumerate(zip(ts, ys)):
        weight = 1.0
        for j, tj in enumerate(ts):
            if j != i:
                weight *= (t - tj) / (ti - tj)
        total += weight * yi
    return total


def zero_crossings(times, values):
    """Times where ``values`` changes sign, refined by bisection on the
    cubic through the two rows on either side of each sign change."""
    crossings = []
    for i in range(len(values) - 1):
        a, b = values[i], values[i + 1]
        if a == 0 or a * b > 0:
            continue
        lo, hi = max(0, i - 1), min(len(values), i + 3)
        ts, ys = times[lo:hi], values[lo:hi]
        left, right = times[i], times[i + 1]
        f_left = a
        for _ in range(60):
            middle = 0.5 * (left + right)
            f_middle = _lagrange(ts, ys, middle)
            if (f_middle > 0) == (f_left > 0):
                left, f_left = middle, f_middle
            else:
                right = middle
        crossings.append(0.5 * (left + right))
    return crossings


def measured_frequency(times, momentum):
    """(omega, number of crossings) from the zero crossings, or None."""
    crossings = zero_crossings(times, momentum)
    if len(crossings) < 2:
        return None
    half_period = (crossings[-1] - crossings[0]) / (len(crossings) - 1)
    return math.pi / half_period, len(crossings)


def mean_time_step(times, dts):
    """The mean time step of a history (the last, shortened step and the
    initial dt = 0 row left out)."""
    steps = [d for d in dts[1:-1] if d > 0] or [d for d in dts if d > 0]
    return sum(steps) / len(steps) if steps else None


def scheme_of(data, row):
    """Keyword arguments of mpm_dispersion for a run's method."""
    def value(path):
        found = data.value(row, path)
        return (found if found is not None else DEFAULTS[path]).strip()

    update = value("Particle update/Model name")
    update = SAME_VELOCITY_UPDATE.get(update, update)
    mass = value("Mass matrix/Model name")
    order = int(float(value("Mass matrix/Fmpm/Order")))
    ppc = int(float(value("Body 0/Points per cell")))
    return ppc, dict(update=update, mass=mass,
                     order=order if mass == "fmpm" else 1,
                     strain=value("Time/Strain update"),
                     strain_mass=value("Time/Strain update mass matrix"),
                     blend=float(value(
                         "Particle update/Flip pic blend/FLIP fraction")))


def analyse(study_path, output, quick, wave_speed, length):
    """Measure and predict; return the CSV rows."""
    import mpm_dispersion  # needs numpy

    study = fmpm_study.parse_study(study_path, quick=quick)
    runs = fmpm_study.expand_runs(study, output)
    rows = fmpm_study.collect_results(study, runs)
    data = fmpm_study.ChartData(study, rows)
    omega = math.pi * wave_speed / (2 * length)
    table = []
    for row in rows:
        if not str(row["status"]).startswith("completed"):
            continue
        series = read_series(row["_run"].directory / "history.csv")
        h = data.cell_size(row)
        if series is None or not h:
            continue
        times, momentum, dts, energies = series
        measured = measured_frequency(times, momentum)
        dt = mean_time_step(times, dts)
        if measured is None or dt is None:
            continue
        omega_h, count = measured
        nu = wave_speed * dt / h
        theta = math.pi * h / (2 * length)
        ppc, scheme = scheme_of(data, row)
        model_error, energy_factor = mpm_dispersion.mode_frequency(
            theta, nu, geometry="1d", ppc=ppc, **scheme)
        periods = times[-1] * omega / (2 * math.pi)
        table.append({
            "run_id": row["run_id"], "method": data.method(row),
            "n": data.resolution(row), "h": h, "theta": theta, "nu": nu,
            "crossings": count,
            "measured": omega_h / omega - 1,
            "fe_lumped": mpm_dispersion.fe_frequency_error_leading(
                theta, nu, "lumped"),
            "fe_consistent": mpm_dispersion.fe_frequency_error_leading(
                theta, nu, "consistent"),
            "mpm_model": model_error,
            "energy_measured": energies[-1] / energies[0],
            "energy_model": energy_factor ** periods,
        })
    return data, table


COLUMNS = [
    ("run_id", "run_id"), ("method", "method"), ("n", "n"), ("h", "h"),
    ("theta", "theta"), ("nu", "nu"), ("crossings", "zero_crossings"),
    ("measured", "frequency_error_measured"),
    ("fe_lumped", "frequency_error_fe_lumped"),
    ("fe_consistent", "frequency_error_fe_consistent"),
    ("mpm_model", "frequency_error_mpm_model"),
    ("energy_measured", "final_energy_ratio_measured"),
    ("energy_model", "final_energy_ratio_mpm_model"),
]


def write_table(path, table):
    with open(path, "w", newline="") as stream:
        writer = csv.writer(stream)
        writer.writerow([name for _, name in COLUMNS])
        for item in table:
            writer.writerow([f"{item[k]:.6g}" if isinstance(item[k], float)
                             else item[k] for k, _ in COLUMNS])


def draw(path, data, table):
    plt = fmpm_study.import_pyplot()
    if plt is None:
        return "matplotlib is not installed"
    methods = list(dict.fromkeys(item["method"] for item in table))
    fig, ax = plt.subplots(figsize=(9.5, 5.5))
    for number, method in enumerate(methods):
        items = sorted((i for i in table if i["method"] == method),
                       key=lambda i: i["h"])
        style = fmpm_study._style(number)
        hs = [i["h"] for i in items]
        coefficients = [i["measured"] / i["theta"] ** 2 for i in items]
        mean = sum(coefficients) / len(coefficients)
        ax.plot(hs, coefficients, label=f"{method} ({mean:+.4f})", **style)
        ax.plot(hs, [i["mpm_model"] / i["theta"] ** 2 for i in items],
                color=style["color"], lw=3, alpha=0.3)
    everything = sorted(table, key=lambda i: i["h"])
    hs = [i["h"] for i in everything]
    ax.plot(hs, [i["fe_lumped"] / i["theta"] ** 2 for i in everything],
            "k--", lw=1, label="FE lumped: -(1-nu^2)/24")
    ax.plot(hs, [i["fe_consistent"] / i["theta"] ** 2 for i in everything],
            "k:", lw=1.2, label="FE consistent: +(1+nu^2)/24")
    ax.axhline(0, color="grey", lw=0.5)
    ax.set_xscale("log")
    ax.set_xlabel("cell size h")
    ax.set_ylabel("relative frequency error / theta^2,  theta = pi h/(2L)")
    ax.set_title(f"{data.study.title}\nfrequency error from the zero "
                 "crossings of momentum_x (wide pale lines: linearised fmpm "
                 "step)", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    fig.tight_layout()
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return None


def main(argv=None):
    parser = argparse.ArgumentParser(
        description="Frequency error of the vibrating bar runs of a study.")
    parser.add_argument("study", help="the study file")
    parser.add_argument("--output", metavar="DIR", help="the study's "
                        "output directory (default as fmpm_study.py)")
    parser.add_argument("--quick", action="store_true",
                        help="the study's quick variant")
    parser.add_argument("--wave-speed", type=float, default=10.0,
                        help="wave speed c (default 10 m/s)")
    parser.add_argument("--length", type=float, default=1.0,
                        help="bar length L (default 1 m)")
    arguments = parser.parse_args(argv)
    output = (Path(arguments.output).resolve() if arguments.output else
              fmpm_study.default_output_dir(arguments.study, arguments.quick))
    try:
        data, table = analyse(arguments.study, output, arguments.quick,
                              arguments.wave_speed, arguments.length)
    except fmpm_study.StudyError as error:
        print(f"frequency_error.py: error in study file: {error}",
              file=sys.stderr)
        return 2
    if not table:
        print("frequency_error.py: no completed run with a history.csv "
              "and two zero crossings of momentum_x", file=sys.stderr)
        return 1
    write_table(output / "frequency_error.csv", table)
    reason = draw(output / "frequency_error.png", data, table)
    print(f"Frequency errors of {len(table)} runs written to "
          f"{output / 'frequency_error.csv'}"
          + (f"; chart skipped: {reason}" if reason else
             f" and {output / 'frequency_error.png'}"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
