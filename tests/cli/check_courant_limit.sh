#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The Courant number is the fraction of the cell-crossing time a step takes;
# the method's measured critical Courant number caps it and does not scale
# it. With the exact full mass matrix (FMPM update, full-mass strain
# velocities, limit LIMIT) the first step of a scene at Courant number 0.4
# is LIMIT/0.4 times the lumped one and the run says so; at a Courant
# number below the limit it equals the lumped one and nothing is said.
#   check_courant_limit.sh FMPM SCENE LIMIT
set -u
fmpm="$1"; scene="$2"; limit="$3"
one_step() { # one_step UPDATE MASS COURANT
  name="$2-$3"
  printf 'subsection Particle update\n set Model name = %s\nend\nsubsection Mass matrix\n set Model name = %s\nend\nsubsection Time\n set Courant number = %s\n set Maximum number of steps = 1\nend\nsubsection Output\n set Directory = output-limit-%s\n set Write vtu = false\n set Interval = 0\n set Step interval = 1\nend\n' "$1" "$2" "$3" "$name" > "limit-$name.prm"
  "$fmpm" "$scene" "limit-$name.prm" > "limit-$name.log" 2>&1 || { cat "limit-$name.log"; echo "FAIL: run with $2 at $3"; exit 1; }
  # dt of the first step (row 3 of history.csv: header, step 0, step 1).
  sed -n 3p "output-limit-$name/history.csv" | cut -d, -f3
}
ratio_is() { # ratio_is A B EXPECTED
  awk -v a="$1" -v b="$2" -v f="$3" 'BEGIN { r = a / b; d = r - f; if (d < 0) d = -d; if (b <= 0 || d > 1e-9 * f) { print "FAIL: dt ratio " r ", expected " f; exit 1 } }'
}
lumped=$(one_step flip lumped 0.4)
full=$(one_step fmpm full 0.4)
echo "C = 0.4: dt lumped $lumped, dt full $full"
grep -F "capped" limit-lumped-0.4.log && { echo "FAIL: the lumped run is capped"; exit 1; }
grep -F "Courant number 0.4 capped at the method's limit $limit (" limit-full-0.4.log || { echo "FAIL: the cap is not printed"; exit 1; }
ratio_is "$full" "$lumped" "$(awk -v l="$limit" 'BEGIN { print l / 0.4 }')" || exit 1
lumped=$(one_step flip lumped 0.1)
full=$(one_step fmpm full 0.1)
echo "C = 0.1: dt lumped $lumped, dt full $full"
grep -F "capped" limit-full-0.1.log && { echo "FAIL: a Courant number below the limit is capped"; exit 1; }
ratio_is "$full" "$lumped" 1 || exit 1
echo PASS
