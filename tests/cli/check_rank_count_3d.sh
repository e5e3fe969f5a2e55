#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The same 3D scene gives the same points and the same physics on 1 and 2
# ranks: two spheres colliding with logistic-regression contact on a box
# mesh that is not a cube (p4est orders its coarse cells otherwise than
# deal.II), head-on (spheres_contact_3d.prm) or oblique
# (spheres_oblique_3d.prm). The points of the first output (id, body, position, ...) must
# be identical; history.csv and every later particles_NNNNN.csv agree to
# 1e-9 (relative, or absolute for the round-off zeros such as shear
# stresses of 1e-12; the order of sums over the ranks differs), and the runs
# take the same number of steps and the same logistic-regression iterations.
#
#   check_rank_count_3d.sh FMPM SCENE -- MPIEXEC NP_FLAG [PREFLAGS...]
set -u
fmpm="$1"; scene="$(realpath "$2")"; shift 3
mpiexec="$1"; np_flag="$2"; shift 2
preflags=("$@")
fail() { echo "FAIL: $*"; exit 1; }
work="rank-count-$(basename "$scene" .prm)"
rm -rf "$work"; mkdir "$work"; cd "$work" || exit 1
printf 'subsection Output\n set Directory = one\nend\n' > one.prm
printf 'subsection Output\n set Directory = two\nend\n' > two.prm
"$fmpm" "$scene" one.prm > one.log 2>&1 || { tail one.log; fail "serial run"; }
"$mpiexec" "$np_flag" 2 "${preflags[@]}" "$fmpm" "$scene" two.prm > two.log 2>&1 \
  || { tail two.log; fail "2-rank run"; }
grep -q "2 MPI rank" two.log || fail "not on 2 ranks"
cmp -s one/particles_00000.csv two/particles_00000.csv \
  || { diff one/particles_00000.csv two/particles_00000.csv | head -6;
       fail "the initial points differ between 1 and 2 ranks"; }
steps() { grep '"n_steps"' "$1/summary.json"; }
[ "$(steps one)" = "$(steps two)" ] || fail "steps: 1 rank $(steps one), 2 ranks $(steps two)"
# Each node's point cloud is in one order on any number of ranks: the
# logistic-regression fits take the same numbers of iterations.
fits() { grep '"logistic_regression_' "$1/summary.json"; }
[ -n "$(fits one)" ] || fail "no logistic-regression statistics in summary.json"
[ "$(fits one)" = "$(fits two)" ] \
  || fail "fits: 1 rank $(fits one | tr -d '\n'), 2 ranks $(fits two | tr -d '\n')"
# The collision happens: the spheres' kinetic energy drops by 5 %.
python3 - one/history.csv <<'PY' || fail "no collision in the serial run"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
k = [float(r["kinetic_energy"]) for r in rows]
sys.exit(0 if min(k) < 0.95 * k[0] else 1)
PY
for file in history.csv $(cd one && ls particles_*.csv); do
  numdiff -q -r 1e-9 -a 1e-9 -s ', \n' "one/$file" "two/$file" \
    || { numdiff -r 1e-9 -a 1e-9 -s ', \n' "one/$file" "two/$file" | head -12;
         fail "$file differs between 1 and 2 ranks"; }
done
echo PASS
