#!/usr/bin/env python3
"""A fake fmpm executable for testing contrib/studies/fmpm_study.py.

Usage: ``fake_fmpm.py a.prm b.prm ...`` (later files override earlier ones).

It reads the deal.II parameter files itself and, instead of simulating,
writes ``summary.json`` and ``history.csv`` into ``Output/Directory`` with
synthetic numbers:

- error_velocity_l2 = C * h**ORDER[method], h = 1 / (first number of
  ``Mesh/Subdivisions``), method = ``Method/Particle update``;
- wall_seconds proportional to n**2 (written, not slept);
- if ``Time/Courant number`` exceeds THRESHOLD[method] the run fails with
  status ``failed: energy growth`` and exit code 1;
- ``Test/Crash = true`` makes it exit with code 3 without any summary;
- ``Test/Sleep = S`` makes it sleep S seconds first (for timeout tests);
- ``Test/No analytical = true`` mimics a scene without an analytical
  solution: no error_* keys, 2n + 1 steps, and in history.csv
  kinetic_energy = 1 + C h**ORDER sin(2 pi t / end time), strain_energy =
  1 - (the same term), total_energy = 2 (for the reference-run tests).

If the environment variable FAKE_FMPM_COUNTER names a file, one line with
the output directory is appended to it per invocation.
"""

import csv
import json
import math
import os
import sys
import time

#: Convergence order of the velocity error per particle update method.
ORDER = {"flip": 2.0, "pic": 1.0, "fmpm": 3.0}

#: Largest stable Courant number per method.
THRESHOLD = {"flip": 0.6, "pic": 1.0, "fmpm": 0.8}

#: Error constant C per method.
CONSTANT = {"flip": 2.0, "pic": 0.5, "fmpm": 4.0}


def parse_prm_text(text, values=None, origin="<text>"):
    """Parse deal.II parameter file text into {'A/B/name': value}.

    Handles ``set``, ``subsection`` and ``end``, and '#' comments; later
    ``set`` lines override earlier ones.  Raises ValueError on unbalanced
    subsections or unknown statements.
    """
    values = {} if values is None else values
    sections = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        if line.startswith("subsection "):
            sections.append(line[len("subsection "):].strip())
        elif line == "end":
            if not sections:
                raise ValueError(f"{origin}:{number}: 'end' without "
                                 "subsection")
            sections.pop()
        elif line.startswith("set ") and "=" in line:
            name, value = line[len("set "):].split("=", 1)
            values["/".join(sections + [name.strip()])] = value.strip()
        else:
            raise ValueError(f"{origin}:{number}: cannot parse '{line}'")
    if sections:
        raise ValueError(f"{origin}: subsection '{sections[-1]}' not closed")
    return values


def parse_prm_files(paths):
    """Parse several parameter files, later ones overriding earlier ones."""
    values = {}
    for path in paths:
        with open(path) as stream:
            parse_prm_text(stream.read(), values, origin=path)
    return values


def main(argv):
    if not argv:
        print("usage: fake_fmpm.py FILE.prm...", file=sys.stderr)
        return 2
    prm = parse_prm_files(argv)
    output = prm.get("Output/Directory", "output")
    os.makedirs(output, exist_ok=True)

    counter = os.environ.get("FAKE_FMPM_COUNTER")
    if counter:
        with open(counter, "a") as stream:
            stream.write(output + "\n")

    time.sleep(float(prm.get("Test/Sleep", "0")))
    if prm.get("Test/Crash", "false").strip().lower() == "true":
        print("fake fmpm: crashing as asked", file=sys.stderr)
        return 3

    subdivisions = [int(s) for s in
                    prm.get("Mesh/Subdivisions", "8").split(",")]
    n = subdivisions[0]
    h = 1.0 / n
    n_cells = 1
    for s in subdivisions:
        n_cells *= s
    method = prm.get("Method/Particle update", "flip")
    order, constant = ORDER.get(method, 2.0), CONSTANT.get(method, 1.0)
    courant = float(prm.get("Time/Courant number", "0.5"))
    end_time = float(prm.get("Time/End time", "0.1"))
    analytical = prm.get("Test/No analytical",
                         "false").strip().lower() != "true"
    n_steps = 20 if analytical else 2 * n + 1
    dt = end_time / n_steps
    points_per_cell = int(prm.get("Body 0/Points per cell", "4"))
    n_particles = n_cells * points_per_cell
    wall = 1e-3 * n * n

    failed = courant > THRESHOLD.get(method, 1.0)
    failure_step = max(1, int(n_steps * THRESHOLD.get(method, 1.0) / courant
                              / 2)) if failed else None
    last_step = failure_step if failed else n_steps

    with open(os.path.join(output, "history.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["step", "time", "dt", "kinetic_energy",
                         "strain_energy", "total_energy", "momentum_x",
                         "momentum_y", "error_velocity_l2"])
        for step in range(last_step + 1):
            t = step * dt
            growth = 1.5 ** step if failed else 1.0 - 0.1 * h * t
            kinetic = 0.5 * growth * (1 + (step % 2) * 0.1)
            total = growth
            if not analytical:
                kinetic = 1 + constant * h ** order * math.sin(
                    2 * math.pi * t / end_time)
                total = 2.0
            writer.writerow([step, t, dt, kinetic, total - kinetic, total,
                             0.0, 0.0, constant * h ** order])

    summary = {
        "dimension": int(prm.get("Dimension", "2")),
        "n_mpi_ranks": 1,
        "n_particles": n_particles,
        "n_cells": n_cells,
        "n_dofs": 2 * (n + 1) * (subdivisions[-1] + 1),
        "n_steps": last_step,
        "end_time": last_step * dt,
        "wall_seconds": wall,
        "particle_steps_per_second": n_particles * last_step / wall,
        "final_kinetic_energy": 0.5,
        "final_strain_energy": 0.5,
    }
    if failed:
        summary.update(status="failed: energy growth",
                       failure_step=failure_step,
                       failure_time=failure_step * dt)
    elif not analytical:
        summary.update(status="completed")
    else:
        summary.update(status="completed",
                       error_velocity_l2=constant * h ** order,
                       error_displacement_l2=0.5 * constant * h ** order,
                       energy_error=h ** order)
    with open(os.path.join(output, "summary.json"), "w") as stream:
        json.dump(summary, stream, indent=2)
    print(f"fake fmpm: {summary['status']}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
