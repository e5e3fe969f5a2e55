#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The cantilever (parameters/cantilever.prm) to t = 1.8 s: with FLIP's
# first-order position update (psi = 0) at Courant 0.4 a checkerboard of J
# grows after the first minimum and fmpm warns once, naming the indicator;
# with psi = 1 (the default auto with USAVG+) the indicator stays below 0.1 and
# nothing warns (doc/studies/cantilever.md). On 2 ranks the indicator is the
# same as on 1.
#   check_cantilever_checkerboard.sh FMPM SCENE MPIEXEC...
set -u
fmpm="$1"; scene="$2"; shift 2
run() { # name psi [launcher...]
  local name="$1" psi="$2"; shift 2
  printf 'subsection Time\n set End time = 1.8\nend\nsubsection Particle update\n subsection Flip\n  set Position update psi = %s\n end\nend\nsubsection Output\n set Directory = output-%s\n set Write vtu = false\n set Interval = 0.05\nend\n' "$psi" "$name" > "$name.prm"
  "$@" "$fmpm" "$scene" "$name.prm" > "$name.log" 2>&1 || { tail -5 "$name.log"; echo "FAIL: $name did not complete"; exit 1; }
}
value() { sed -n "s/.*\"$2\": \([-0-9.e+]*\).*/\1/p" "output-$1/summary.json"; }
run cantilever-psi0 0
run cantilever-psi1 1
run cantilever-psi0-np2 0 "$@"
n0="$(grep -c 'warning: the checkerboard indicator of J' cantilever-psi0.log)"
n1="$(grep -c 'warning: the checkerboard indicator of J' cantilever-psi1.log)"
c0="$(value cantilever-psi0 max_checkerboard_j)"
c1="$(value cantilever-psi1 max_checkerboard_j)"
c2="$(value cantilever-psi0-np2 max_checkerboard_j)"
echo "psi = 0: $n0 warning(s), max_checkerboard_j $c0 (2 ranks: $c2); psi = 1: $n1 warning(s), max_checkerboard_j $c1"
[ "$n0" -eq 1 ] || { echo "FAIL: psi = 0 should warn once"; exit 1; }
[ "$n1" -eq 0 ] || { echo "FAIL: psi = 1 should not warn"; exit 1; }
awk -v a="$c0" -v b="$c1" 'BEGIN { exit !(a > 0.1 && b < 0.06) }' || { echo "FAIL: indicator values"; exit 1; }
awk -v a="$c0" -v b="$c2" 'BEGIN { d = a - b; exit !(d < 1e-6 * a && -d < 1e-6 * a) }' || { echo "FAIL: 1 and 2 ranks differ"; exit 1; }
echo PASS
