#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The shock scene on 1 and 2 ranks (mie gruneisen, moving wall, CPDI,
# XPIC(5)): particles_NNNNN.csv is gathered from both ranks (every point,
# the header) and equals the serial file point by point to 1e-7 of each
# column's range; history.csv to 1e-8.
set -u
fmpm="$1"; source_dir="$2"; shift 2
mpiexec=("$@")
for ranks in 1 2; do
  rm -rf "output-shock-mpi-$ranks"
  printf 'subsection Mesh\n set Upper corner = 0.0105, 0.0005\n set Subdivisions = 42, 2\nend\nsubsection Body 0\n set Center = 0.005, 0.00025\n set Half lengths = 0.005, 0.00025\nend\nsubsection Boundary conditions\n subsection Moving wall 0\n  set Function constants = u=1000, right=0.01\n end\nend\nsubsection Time\n set End time = 1e-6\nend\nsubsection Output\n set Interval = 0.5e-6\n set Directory = output-shock-mpi-%s\nend\n' "$ranks" > "shock-mpi-$ranks.prm"
done
scene="$source_dir/../../parameters/shock_nickel.prm"
# Debian's python3 (numpy), also when another python3 comes first on PATH.
python=python3
[ -x /usr/bin/python3 ] && python=/usr/bin/python3
"$fmpm" "$scene" shock-mpi-1.prm > shock-log-1.txt 2>&1 || { tail shock-log-1.txt; echo "FAIL: serial run"; exit 1; }
"${mpiexec[@]}" "$fmpm" "$scene" shock-mpi-2.prm > shock-log-2.txt 2>&1 || { tail shock-log-2.txt; echo "FAIL: 2-rank run"; exit 1; }
grep -q "2 MPI rank" shock-log-2.txt || { echo "FAIL: not on 2 ranks"; exit 1; }
for n in 00001 00002; do
  a="output-shock-mpi-1/particles_$n.csv"; b="output-shock-mpi-2/particles_$n.csv"
  [ -s "$a" ] && [ -s "$b" ] || { echo "FAIL: missing $a or $b"; exit 1; }
  [ "$(wc -l < "$a")" = 321 ] || { echo "FAIL: $a has $(wc -l < "$a") lines, expected 321"; exit 1; }
  head -1 "$a" | grep -q '^id,body,material,x,y,vx,vy,stress_xx,stress_yy,stress_xy,pressure,J,internal_energy,plastic_strain$' \
    || { head -1 "$a"; echo "FAIL: header"; exit 1; }
  # Point ids depend on the number of ranks: match the points by position.
  "$python" - "$a" "$b" <<'PY' || { echo "FAIL: $n differs on 2 ranks"; exit 1; }
import sys
import numpy as np
a, b = (np.genfromtxt(f, delimiter=",", names=True) for f in sys.argv[1:3])
order = [np.lexsort((np.round(t["x"], 9), np.round(t["y"], 9))) for t in (a, b)]
a, b = a[order[0]], b[order[1]]
# Velocities against the largest speed, stresses against the largest stress.
groups = {"v": ("vx", "vy"), "s": ("stress_xx", "stress_yy", "stress_xy",
                                   "pressure")}
def scale(name):
    for members in groups.values():
        if name in members:
            return max(np.abs(a[m]).max() for m in members)
    return max(np.abs(a[name]).max(), 1e-30)
for name in a.dtype.names[1:]:
    error = np.abs(a[name] - b[name]).max() / scale(name)
    if error > 1e-7:
        sys.exit(f"column {name}: largest difference {error:.3g} of its range")
PY
done
numdiff -q -r 1e-8 -a 1e-6 -s ', \n' output-shock-mpi-1/history.csv output-shock-mpi-2/history.csv \
  || { numdiff -r 1e-8 -a 1e-6 -s ', \n' output-shock-mpi-1/history.csv output-shock-mpi-2/history.csv | head; echo "FAIL: history differs"; exit 1; }
echo PASS
