#!/usr/bin/env python3
# SPDX-License-Identifier: LGPL-2.1-or-later
"""fmpm against NairnMPM on the axisymmetric twins: hold-phase stresses and speed.

Usage: axisymmetric_twins.py --fmpm FMPM [--scenes cylinder disk]
                             [--shapes cpdi ugimp] [--repeat N]
                             [--output DIR] [--no-nairn]

Scenes: 'cylinder' is parameters/axial_load_cylinder.prm against
contrib/utilities/nairn_axial_cylinder.sh, 'disk' is
parameters/radial_pressure_disk.prm against nairn_radial_disk.sh (the same
geometry, material, load ramp and hold, cells and points; fmpm 'cpdi' is
NairnMPM's lCPDI, 'ugimp' its uGIMP).

For each scene and shape function it
1. runs fmpm once with particle CSVs at 200 outputs and takes the mean over
   the points of stress_xx (sigma_rr), stress_yy (sigma_zz) and stress_hoop
   (sigma_thetatheta), averaged over the outputs of the last tenth of the run
   (the hold phase; NairnMPM's scripts average their global archive the same
   way), and the same means without the points of the loaded cell
   (reported, not checked; the scenes integrate the traction over the
   loaded points' faces, Traction/Distribution = face, as NairnMPM does);
2. times N pairs of runs, fmpm (no output but the first and last) and
   NairnMPM (1 thread), interleaved fmpm, NairnMPM, fmpm, ..., one process
   at a time, and reports particle-steps per second of each run counted two
   ways, the same for both codes: points x steps / wall seconds of the whole
   process (start-up included), and points x steps / wall seconds of the
   run as the code reports it (time steps and their output, without the
   process start-up: fmpm's TimerOutput total, NairnMPM's "Elapsed Time per
   Step" times its steps).

Prints a Markdown table and writes twins.csv in DIR. Exit status 1 when a
hold-phase mean is more than 1 % from exact or from NairnMPM's mean.
"""
import argparse
import csv
import glob
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
E, NU = 2.3e9, 0.33
SCENES = {
    "cylinder": {
        "prm": ROOT / "parameters" / "axial_load_cylinder.prm",
        "nairn": ROOT / "contrib" / "utilities" / "nairn_axial_cylinder.sh",
        # sigma_rr, sigma_zz, sigma_thetatheta (Pa)
        "exact": (NU / (1 - NU) * -2.3e6, -2.3e6, NU / (1 - NU) * -2.3e6),
        # the points of the loaded cell (top, z > L - h)
        "loaded": lambda r, z: z > 0.018,
    },
    "disk": {
        "prm": ROOT / "parameters" / "radial_pressure_disk.prm",
        "nairn": ROOT / "contrib" / "utilities" / "nairn_radial_disk.sh",
        "exact": (-2.3e6, 2 * NU * -2.3e6, -2.3e6),
        # the points of the loaded cell (outer, r > b - h)
        "loaded": lambda r, z: r > 0.0475,
    },
}
NAIRN_SHAPE = {"cpdi": "lCPDI", "ugimp": "uGIMP", "classic": "Dirac"}
COMPONENTS = ("sigma_rr", "sigma_zz", "sigma_thetatheta")
FMPM_COLUMNS = ("stress_xx", "stress_yy", "stress_hoop")
TOLERANCE = 0.01


def run_fmpm(fmpm, scene_prm, overrides, workdir):
    """Runs fmpm on the scene plus an override file; returns wall seconds
    of the process and of the run (its TimerOutput total)."""
    override = Path(workdir) / "override.prm"
    override.write_text(overrides)
    start = time.perf_counter()
    result = subprocess.run([fmpm, str(scene_prm), str(override)], cwd=workdir,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    wall = time.perf_counter() - start
    if result.returncode != 0:
        sys.exit(f"fmpm failed on {scene_prm}:\n{result.stdout[-2000:]}")
    m = re.search(r"Total wallclock time elapsed since start\s*\|\s*([0-9.e+-]+)s",
                  result.stdout)
    return wall, float(m.group(1)) if m else float("nan")


def read_history(directory):
    with open(Path(directory) / "history.csv") as f:
        rows = [l for l in f if not l.startswith("#")]
    return list(csv.DictReader(rows))


def fmpm_hold_means(fmpm, scene, shape, workdir):
    """Hold-phase means of the three stresses (Pa) over all points and over
    the points outside the loaded cell, points and steps."""
    out = Path(workdir) / f"stress_{scene}_{shape}"
    run_fmpm(fmpm, SCENES[scene]["prm"],
             f"subsection Shape function\n  set Type = {shape}\nend\n"
             f"subsection Output\n  set Directory = {out}\nend\n", workdir)
    files = sorted(glob.glob(str(out / "particles_*.csv")))
    first = int(0.9 * (len(files) - 1))
    loaded = SCENES[scene]["loaded"]
    sums, inner_sums, n_points = [0.0] * 3, [0.0] * 3, 0
    for name in files[first:]:
        with open(name, newline="") as f:
            rows = list(csv.DictReader(f))
        n_points = len(rows)
        inner = [r for r in rows if not loaded(float(r["x"]), float(r["y"]))]
        for c, column in enumerate(FMPM_COLUMNS):
            sums[c] += sum(float(r[column]) for r in rows) / len(rows)
            inner_sums[c] += sum(float(r[column]) for r in inner) / len(inner)
    means = [s / len(files[first:]) for s in sums]
    inner_means = [s / len(files[first:]) for s in inner_sums]
    steps = int(read_history(out)[-1]["step"])
    return means, inner_means, n_points, steps


def time_fmpm(fmpm, scene, shape, workdir):
    out = Path(workdir) / f"timing_{scene}_{shape}"
    wall, run_wall = run_fmpm(
        fmpm, SCENES[scene]["prm"],
        f"subsection Shape function\n  set Type = {shape}\nend\n"
        f"subsection Output\n  set Directory = {out}\n  set Interval = 0\n"
        f"  set Step interval = 1000000000\n  set Write particle csv = false\n"
        f"end\n", workdir)
    return wall, run_wall, int(read_history(out)[-1]["step"])


def run_nairn(scene, shape):
    """Runs the NairnMPM twin script; returns its printed figures."""
    env = dict(os.environ, SHAPE=NAIRN_SHAPE[shape])
    result = subprocess.run(["bash", str(SCENES[scene]["nairn"]), "1"], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    if result.returncode != 0:
        sys.exit(f"NairnMPM twin failed:\n{result.stdout[-2000:]}")
    text = result.stdout
    figures = {k: float(v) for k, v in
               re.findall(r"(points|steps|wall_s|steps_wall_s)=([0-9.e+-]+)",
                          text)}
    for name in COMPONENTS:
        m = re.search(rf"{name}: .*?mean_last_tenth=([0-9.e+-]+)", text)
        figures[name] = float(m.group(1)) * 1e6  # MPa -> Pa
    return figures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmpm", required=True)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES))
    parser.add_argument("--shapes", nargs="+", default=["cpdi", "ugimp"])
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--output", default=None)
    parser.add_argument("--no-nairn", action="store_true",
                        help="only fmpm's stresses against exact")
    args = parser.parse_args()
    fmpm = str(Path(args.fmpm).resolve())
    workdir = Path(args.output or tempfile.mkdtemp(prefix="twins."))
    workdir.mkdir(parents=True, exist_ok=True)

    rows, failed = [], []
    print("| scene | shape | code | points | steps | " +
          " | ".join(f"{c} MPa (vs exact)" for c in COMPONENTS) +
          " | wall s (run) | particle-steps/s (run) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for scene in args.scenes:
        exact = SCENES[scene]["exact"]
        for shape in args.shapes:
            means, inner_means, n_points, steps = fmpm_hold_means(
                fmpm, scene, shape, workdir)
            nairn = None if args.no_nairn else run_nairn(scene, shape)
            walls = {"fmpm": [], "NairnMPM": []}
            for _ in range(args.repeat):
                wall, run_wall, steps = time_fmpm(fmpm, scene, shape, workdir)
                walls["fmpm"].append((wall, run_wall, steps, n_points))
                if not args.no_nairn:
                    n = run_nairn(scene, shape)
                    walls["NairnMPM"].append((n["wall_s"], n["steps_wall_s"],
                                              int(n["steps"]),
                                              int(n["points"])))
            for code, stresses in (("fmpm", means),
                                   ("NairnMPM", nairn and
                                    [nairn[c] for c in COMPONENTS])):
                if stresses is None:
                    continue
                for c, (s, x) in enumerate(zip(stresses, exact)):
                    if abs(s / x - 1) > TOLERANCE:
                        failed.append(f"{scene} {shape} {code} "
                                      f"{COMPONENTS[c]}: {s:.6g} vs exact "
                                      f"{x:.6g}")
                    if code == "fmpm" and nairn:
                        ref = nairn[COMPONENTS[c]]
                        if abs(s / ref - 1) > TOLERANCE:
                            failed.append(f"{scene} {shape} {COMPONENTS[c]}: "
                                          f"fmpm {s:.6g} vs NairnMPM "
                                          f"{ref:.6g}")
                timings = walls[code]
                rates = [p * st / w for w, _, st, p in timings]
                run_rates = [p * st / w for _, w, st, p in timings]
                cells = " | ".join(f"{s / 1e6:.5f} ({s / x - 1:+.1e})"
                                   for s, x in zip(stresses, exact))
                print(f"| {scene} | {shape} | {code} | "
                      f"{timings[0][3] if timings else n_points} | "
                      f"{timings[0][2] if timings else steps} | {cells} | "
                      f"{', '.join(f'{w:.2f} ({r:.2f})' for w, r, _, _ in timings)} | "
                      f"{', '.join(f'{r:.3g} ({q:.3g})' for r, q in zip(rates, run_rates))} |")
                rows.append({"scene": scene, "shape": shape, "code": code,
                             **{c: s for c, s in zip(COMPONENTS, stresses)},
                             "walls": " ".join(f"{w:.3f}"
                                               for w, _, _, _ in timings),
                             "run_walls": " ".join(f"{w:.3f}"
                                                   for _, w, _, _ in timings),
                             "particle_steps_per_s": " ".join(
                                 f"{r:.4g}" for r in rates),
                             "run_particle_steps_per_s": " ".join(
                                 f"{r:.4g}" for r in run_rates)})
            cells = " | ".join(f"{s / 1e6:.5f} ({s / x - 1:+.1e})"
                               for s, x in zip(inner_means, exact))
            print(f"| {scene} | {shape} | fmpm, outside the loaded cell | "
                  f"| | {cells} | | |")
            rows.append({"scene": scene, "shape": shape,
                         "code": "fmpm, outside the loaded cell",
                         **dict(zip(COMPONENTS, inner_means)),
                         "walls": "", "run_walls": "",
                         "particle_steps_per_s": "",
                         "run_particle_steps_per_s": ""})
    with open(workdir / "twins.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    print(f"load: {os.getloadavg()[0]:.1f}; results in {workdir}/twins.csv")
    if failed:
        print("more than 1 % off:\n  " + "\n  ".join(failed))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
