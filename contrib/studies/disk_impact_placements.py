#!/usr/bin/env python3
"""The disk impact's energy loss over placements of the disks on the grid,
fmpm and (optionally) its NairnMPM twin on the same point sets.

Placement k moves both disks of parameters/disk_impact.prm by
k (0.037, 0.061) mm: the points stay on the cell lattice (2x2 a cell), so
each k is another staircase of the same disks, with the same points in
both codes. The energy lost, 1 - (kinetic + strain)_end / (kinetic +
strain)_0, moves by tenths of a point from one placement to the next, in
both codes: a single placement does not rank two codes.

One progress line and one CSV row (code, shape, method, k, points, steps,
energy_lost_percent, wall_s) per run, appended to
OUTPUT/disk_impact_placements.csv; rows already there are skipped
(resumable). Then the mean, range and paired differences per shape and
method. doc/studies/bsplines.md, "The disk impact".

Usage::

    disk_impact_placements.py --fmpm BUILD/applications/fmpm/fmpm \\
        [--nairn] [--output DIR] [--shapes b2spline,b2gimp,b2cpdi]
        [--methods flip,fmpm5] [--placements 0,1,2,3,4,5]
"""

import argparse
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "parameters" / "disk_impact.prm"
NAIRN = ROOT / "contrib" / "utilities" / "nairn_disk_impact.sh"
STEP_MM = (0.037, 0.061)
NAIRN_SHAPES = {"cpdi": "lCPDI", "b2spline": "B2SPLINE", "b2gimp": "B2GIMP",
                "b2cpdi": "B2CPDI", "ugimp": "uGIMP", "classic": "Classic"}
FIELDS = ["code", "shape", "method", "k", "points", "steps",
          "energy_lost_percent", "wall_s"]


def offset_mm(k):
    return (round(k * STEP_MM[0], 9), round(k * STEP_MM[1], 9))


def fmpm_overrides(shape, method, k, directory):
    dx, dy = (v * 1e-3 for v in offset_mm(k))
    mass = ""
    if method.startswith("fmpm"):
        mass = f"""subsection Mass matrix
  set Model name = fmpm
  subsection Fmpm
    set Order = {int(method[4:])}
  end
end
"""
    return f"""subsection Shape function
  set Type = {shape}
end
subsection Particle update
  set Model name = {"fmpm" if method.startswith("fmpm") else "flip"}
end
{mass}subsection Body 0
  set Center = {0.0115 + dx!r}, {0.012 + dy!r}
end
subsection Body 1
  set Center = {0.0325 + dx!r}, {0.012 + dy!r}
end
subsection Output
  set Directory = {directory}
  set Write particle csv = false
end
"""


def energy_lost(history):
    rows = list(csv.DictReader(open(history)))

    def energy(r):
        return float(r["kinetic_energy"]) + float(r["strain_energy"])

    return 100 * (1 - energy(rows[-1]) / energy(rows[0])), rows[-1]["step"]


def run_fmpm(binary, shape, method, k):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out"
        prm = Path(tmp) / "overrides.prm"
        prm.write_text(fmpm_overrides(shape, method, k, out))
        start = time.time()
        log = subprocess.run([binary, str(SCENE), str(prm)], cwd=tmp,
                             capture_output=True, text=True)
        wall = time.time() - start
        if log.returncode != 0:
            sys.exit(f"fmpm failed ({shape}, {method}, k = {k}):\n"
                     + log.stdout[-2000:] + log.stderr[-2000:])
        points = next((w for line in log.stdout.splitlines()
                       if "material points" in line
                       for w, nxt in zip(line.split(), line.split()[1:])
                       if nxt == "material"), "?")
        lost, steps = energy_lost(out / "history.csv")
    return {"points": points, "steps": steps,
            "energy_lost_percent": f"{lost:.3f}", "wall_s": f"{wall:.1f}"}


def run_nairn(shape, method, k):
    dx, dy = offset_mm(k)
    env = {"SHAPE": NAIRN_SHAPES[shape], "DX": repr(dx), "DY": repr(dy)}
    log = subprocess.run([str(NAIRN), method.upper()],
                         env={**os.environ, **env},
                         capture_output=True, text=True)
    line = log.stdout.strip().splitlines()[-1] if log.stdout.strip() else ""
    if log.returncode != 0 or "energy_lost=" not in line:
        sys.exit(f"NairnMPM failed ({shape}, {method}, k = {k}):\n"
                 + log.stdout[-2000:] + log.stderr[-2000:])
    fields = dict(w.split("=", 1) for w in line.split() if "=" in w)
    return {"points": fields["points"], "steps": fields["steps"],
            "energy_lost_percent": fields["energy_lost"].rstrip("%"),
            "wall_s": fields["wall_s"]}


def summary(rows, codes):
    print("\nshape method code: energy lost (%) over placements, "
          "mean [min, max]; paired: fmpm - NairnMPM placement by placement")
    keys = sorted({(r["shape"], r["method"]) for r in rows})
    for shape, method in keys:
        by_code = {}
        for code in codes:
            by_code[code] = {int(r["k"]): float(r["energy_lost_percent"])
                             for r in rows if r["code"] == code
                             and r["shape"] == shape and r["method"] == method}
        for code, values in by_code.items():
            if values:
                v = list(values.values())
                print(f"{shape} {method} {code}: {statistics.mean(v):.2f} "
                      f"[{min(v):.2f}, {max(v):.2f}] over {len(v)}")
        if len(codes) == 2:
            common = sorted(set(by_code["fmpm"]) & set(by_code["nairn"]))
            if common:
                diff = [by_code["fmpm"][k] - by_code["nairn"][k]
                        for k in common]
                error = (statistics.stdev(diff) / len(diff) ** 0.5
                         if len(diff) > 1 else float("nan"))
                print(f"{shape} {method} paired: mean {statistics.mean(diff):+.2f}"
                      f" ± {error:.2f} (standard error) "
                      f"[{min(diff):+.2f}, {max(diff):+.2f}] over {len(diff)}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmpm", required=True)
    parser.add_argument("--nairn", action="store_true",
                        help="also run NairnMPM (nairn_disk_impact.sh)")
    parser.add_argument("--output", default=".")
    parser.add_argument("--shapes", default="b2spline,b2gimp,b2cpdi")
    parser.add_argument("--methods", default="flip,fmpm5")
    parser.add_argument("--placements", default="0,1,2,3,4,5")
    args = parser.parse_args()
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    table = output / "disk_impact_placements.csv"
    rows = list(csv.DictReader(open(table))) if table.exists() else []
    done = {(r["code"], r["shape"], r["method"], r["k"]) for r in rows}
    codes = ["fmpm"] + (["nairn"] if args.nairn else [])
    runs = [(code, shape, method, k)
            for shape in args.shapes.split(",")
            for method in args.methods.split(",")
            for k in args.placements.split(",")
            for code in codes]
    for n, (code, shape, method, k) in enumerate(runs, 1):
        if (code, shape, method, k) in done:
            continue
        result = (run_fmpm(args.fmpm, shape, method, int(k)) if code == "fmpm"
                  else run_nairn(shape, method, int(k)))
        row = {"code": code, "shape": shape, "method": method, "k": k,
               **result}
        new = not table.exists()
        with open(table, "a", newline="") as f:
            writer = csv.DictWriter(f, fieldnames=FIELDS)
            if new:
                writer.writeheader()
            writer.writerow(row)
        rows.append(row)
        print(f"[{n}/{len(runs)}] {code} {shape} {method} k={k}: "
              f"{row['energy_lost_percent']} % lost, {row['points']} points, "
              f"{row['steps']} steps, {row['wall_s']} s", flush=True)
    summary(rows, codes)


if __name__ == "__main__":
    main()
