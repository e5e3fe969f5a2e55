#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Periodic FMPM(k) (Mass matrix/Fmpm/Period, Period time) on the colliding
# disks at Courant 0.3 (below periodic FMPM(5)'s limit 0.35: every run takes
# FLIP's time steps):
#  1. Period = 1 is FMPM(k): history.csv and the points bit for bit.
#  2. A period longer than the run is FLIP with the lumped mass matrix, bit
#     for bit (no step uses the series).
#  3. Period = 5: the series in every fifth step (summary.json's
#     fmpm_series_steps), and a result that is neither FLIP's nor FMPM(5)'s.
#  4. Period time: the series in the first step and in each step that
#     crosses a multiple of it.
#
#   check_periodic_fmpm.sh FMPM SCENE
set -u
fmpm="$1"; scene="$(realpath "$2")"
fail() { echo "FAIL: $*"; exit 1; }
rm -rf periodic-fmpm; mkdir periodic-fmpm; cd periodic-fmpm || exit 1
run() { # run NAME UPDATE MASS EXTRA
  printf 'subsection Output\n set Directory = %s\n set Write vtu = false\n set Write particle csv = true\n set Interval = 0.1\nend\nsubsection Time\n set End time = 1.5\n set Courant number = 0.3\nend\nsubsection Timer\n set Type = none\nend\nsubsection Particle update\n set Model name = %s\nend\nsubsection Mass matrix\n set Model name = %s\n subsection Fmpm\n  set Order = 5\n%b end\nend\n' "$1" "$2" "$3" "$4" > "$1.prm"
  "$fmpm" "$scene" "$1.prm" > "$1.log" 2>&1 || { tail "$1.log"; fail "run $1"; }
}
same() { # same DIR_A DIR_B: history and last points bit for bit
  cmp -s "$1/history.csv" "$2/history.csv" && cmp -s "$1/particles_00015.csv" "$2/particles_00015.csv"
}
value() { sed -n "s/.*\"$2\": \([0-9.e+-]*\).*/\1/p" "$1/summary.json"; }

run fmpm5 xpic fmpm ""
run period1 xpic fmpm "  set Period = 1\n"
same fmpm5 period1 || fail "Period = 1 differs from FMPM(5)"

run flip flip lumped ""
run never xpic fmpm "  set Period = 1000000\n"
same flip never || fail "a period longer than the run differs from FLIP with the lumped mass matrix"
[ "$(value never fmpm_series_steps)" = 0 ] || fail "series steps in a run shorter than the period: $(value never fmpm_series_steps)"

run period5 xpic fmpm "  set Period = 5\n"
steps=$(value period5 n_steps); series=$(value period5 fmpm_series_steps)
echo "Period 5: $series series steps of $steps"
[ "$series" = "$((steps / 5))" ] || fail "Period = 5: $series series steps in $steps steps, expected $((steps / 5))"
same period5 flip && fail "Period = 5 equals FLIP"
same period5 fmpm5 && fail "Period = 5 equals FMPM(5)"

run period_time xpic fmpm "  set Period time = 0.1\n"
series=$(value period_time fmpm_series_steps)
echo "Period time 0.1: $series series steps to t = 1.5"
# The first step and one step per crossing of 0.1, 0.2, ..., 1.5.
[ "$series" -ge 15 ] && [ "$series" -le 16 ] || fail "Period time = 0.1: $series series steps to t = 1.5, expected 15-16"
echo PASS
