#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Load balancing by points on a mesh that is never adapted
# (parameters/two_blocks_gap.prm: two blocks of different sizes on an
# 8 x 25 mesh, 2 ranks, 2 steps). With Mesh refinement/Point weight = 0 the
# cells are balanced and one rank holds 1.128x the mean points; with the
# default weight the partition before the first step balances the points
# (summary.json point_imbalance below 1.03).
#
#   check_point_balance.sh FMPM SCENE -- MPIEXEC NP_FLAG [MPIEXEC_PREFLAGS...]
set -u
fmpm="$1"; scene="$(realpath "$2")"; shift 3
mpiexec="$1"; np_flag="$2"; shift 2
preflags=("$@")
fail() { echo "FAIL: $*"; exit 1; }
rm -rf point-balance; mkdir point-balance; cd point-balance || exit 1
imbalance() { # imbalance WEIGHT
  printf 'subsection Output\n set Directory = weight-%s\nend\nsubsection Timer\n set Type = none\nend\nsubsection Time\n set Maximum number of steps = 2\nend\nsubsection Mesh refinement\n set Point weight = %s\nend\n' "$1" "$1" > "weight-$1.prm"
  "$mpiexec" "$np_flag" 2 "${preflags[@]}" "$fmpm" "$scene" "weight-$1.prm" > "weight-$1.log" 2>&1 || { tail "weight-$1.log"; fail "run with Point weight = $1"; }
  sed -n 's/.*"point_imbalance": \([0-9.e+-]*\).*/\1/p' "weight-$1/summary.json"
}
cells=$(imbalance 0)
points=$(imbalance 10)
echo "point_imbalance: cells balanced $cells, points balanced $points"
awk -v a="$cells" 'BEGIN { exit !(a > 1.1) }' || fail "cell partition: expected an imbalance above 1.1, got $cells"
awk -v a="$points" 'BEGIN { exit !(a < 1.03) }' || fail "point-weighted partition: expected below 1.03, got $points"
echo PASS
