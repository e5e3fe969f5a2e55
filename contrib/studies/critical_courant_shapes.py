#!/usr/bin/env python3
"""Critical Courant numbers of FMPM(k) with the FMPM update per shape
function and strain update, by bisection on the vibrating bar.

Each run: parameters/vibrating_bar.prm (32 cells in the bar, 2 points per
cell) with v0 = 1e-3, 20 periods (End time = 8), `Courant number limit =
none`; unstable as in the B-spline study (bsplines.is_unstable): the run
does not complete (energy growth or loss bound) or the energy drifts by
more than 1 % (|energy_error| > 0.01). Seven bisection
steps in [0.1, 1.6] give a bracket of width 0.012. One progress line and
one CSV row (shape, strain update, k, stable, unstable) per bisection,
appended to OUTPUT/critical_courant_shapes.csv; rows already there are
skipped (resumable).

The lower ends, to two decimals, are the table of
Stability::shape_order_limit() (source/time_step_stability.cc) where they
lie below Stability::fmpm_order_limit(); doc/studies/stability.md,
"Shape functions and strain updates".

Usage::

    critical_courant_shapes.py --fmpm BUILD/applications/fmpm/fmpm \\
        [--output DIR] [--shapes classic,ugimp,...] [--schemes usl,usavg]
        [--orders 2,3,5,10] [--scene PRM] [--tag NAME]
"""

import argparse
import csv
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "contrib" / "studies" / "bsplines"))

from bsplines import is_unstable  # noqa: E402  (the criterion of bsplines.md)

SHAPES = "classic,ugimp,cpgimp,cpdi,b2spline,b2gimp,b2cpdi,b3spline"


def overrides(shape, k, scheme, courant, directory):
    mass = "fmpm" if k > 1 else "lumped"
    update = "fmpm" if k > 1 else "flip"
    return f"""subsection Shape function
  set Type = {shape}
end
subsection Mass matrix
  set Model name = {mass}
  subsection Fmpm
    set Order = {max(k, 2)}
  end
end
subsection Particle update
  set Model name = {update}
end
subsection Time
  set Courant number       = {courant}
  set Courant number limit = none
  set Strain update        = {scheme}
  set End time             = 8
end
subsection Body 0
  set Initial velocity = 1e-3*sin(beta*x); 0
end
subsection Reference solution
  set Enable = false
end
subsection Output
  set Directory          = {directory}
  set Interval           = 0.1
  set Write particle csv = false
end
subsection Timer
  set Type = none
end
"""


def stable(fmpm, scene, shape, k, scheme, courant):
    with tempfile.TemporaryDirectory() as work:
        work = Path(work)
        (work / "over.prm").write_text(
            overrides(shape, k, scheme, courant, work / "out"))
        subprocess.run([fmpm, str(scene), str(work / "over.prm")],
                       capture_output=True, text=True)
        try:
            summary = json.loads((work / "out" / "summary.json").read_text())
        except (OSError, ValueError):
            return False
        return not is_unstable(summary)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--fmpm", required=True)
    parser.add_argument("--output", default="critical_courant_shapes")
    parser.add_argument("--shapes", default=SHAPES)
    parser.add_argument("--schemes", default="usl,usavg,usf,usl+,usavg+")
    parser.add_argument("--orders", default="2,3,5,10")
    parser.add_argument("--scene",
                        default=str(ROOT / "parameters" / "vibrating_bar.prm"))
    parser.add_argument("--tag", default="open knots",
                        help="the scene's name in the CSV")
    args = parser.parse_args()
    output = Path(args.output)
    output.mkdir(parents=True, exist_ok=True)
    table = output / "critical_courant_shapes.csv"
    done = set()
    if table.exists():
        with table.open() as f:
            done = {(r["scene"], r["shape"], r["strain_update"], r["k"])
                    for r in csv.DictReader(f)}
    else:
        table.write_text("scene,shape,strain_update,k,stable,unstable\n")
    for scheme in args.schemes.split(","):
        for shape in args.shapes.split(","):
            for k in [int(x) for x in args.orders.split(",")]:
                if (args.tag, shape, scheme, str(k)) in done:
                    continue
                low, high = 0.1, 1.6
                for _ in range(7):
                    courant = round((low + high) / 2, 4)
                    if stable(args.fmpm, args.scene, shape, k, scheme,
                              courant):
                        low = courant
                    else:
                        high = courant
                print(f"{args.tag}: {shape}, {scheme}, FMPM({k}): stable at "
                      f"{low}, unstable at {high}", flush=True)
                with table.open("a") as f:
                    f.write(f"{args.tag},{shape},{scheme},{k},{low},{high}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
