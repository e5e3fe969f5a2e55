#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The automatic time step multiplies the Courant number by the method's
# stability factor: the first step of a scene run with the exact full mass
# matrix (FMPM update) is FACTOR times the first step of the same scene with
# the lumped mass matrix, and the factor is printed at start-up.
#   check_stability_factor.sh FMPM SCENE FACTOR
set -u
fmpm="$1"; scene="$2"; factor="$3"
one_step() {
  printf 'subsection Particle update\n set Model name = %s\nend\nsubsection Mass matrix\n set Model name = %s\nend\nsubsection Time\n set Maximum number of steps = 1\nend\nsubsection Output\n set Directory = output-factor-%s\n set Write vtu = false\n set Interval = 0\n set Step interval = 1\nend\n' "$1" "$2" "$2" > "factor-$2.prm"
  "$fmpm" "$scene" "factor-$2.prm" > "factor-$2.log" 2>&1 || { cat "factor-$2.log"; echo "FAIL: run with $2"; exit 1; }
  # dt of the first step (row 3 of history.csv: header, step 0, step 1).
  sed -n 3p "output-factor-$2/history.csv" | cut -d, -f3
}
dt_lumped="$(one_step flip lumped)"
dt_full="$(one_step fmpm full)"
echo "dt lumped $dt_lumped, dt full $dt_full"
grep -F "stability factor 1 (lumped mass matrix)" factor-lumped.log || { echo "FAIL: factor 1 not printed"; exit 1; }
grep -F "stability factor $factor (" factor-full.log || { echo "FAIL: factor $factor not printed"; exit 1; }
awk -v a="$dt_full" -v b="$dt_lumped" -v f="$factor" 'BEGIN { r = a / b; d = r - f; if (d < 0) d = -d; if (b <= 0 || d > 1e-3) { print "FAIL: dt ratio " r ", expected " f; exit 1 } }' || exit 1
echo PASS
