#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Checkpoint and restart: a run interrupted and resumed with --resume gives
# the uninterrupted run's results.
#
#   check_resume.sh FMPM NAME FULL_RANKS RESUME_RANKS MODE INTERVAL STOP \
#                   SCENE... -- MPIEXEC NP_FLAG [MPIEXEC_PREFLAGS...]
#
# MODE: how the first run of the interrupted pair stops (checkpoints every
# INTERVAL steps):
#   steps   Time/Maximum number of steps = STOP (after the last checkpoint)
#   signal  SIGTERM on the last rank after step STOP: exit code 3, status
#           "stopped: signal", a checkpoint at that step
#   kill    the process dies in the checkpoint of step STOP after writing
#           its temporary files: the previous checkpoint must be used
# Same rank counts: history.csv, the physics of summary.json, the points
# (test output) and the last particle VTU must be bitwise identical; other
# rank counts: equal to round-off (numdiff -r 1e-9; points printed with 9
# digits: -r 1e-7).
set -u
fmpm="$1"; name="$2"; full_ranks="$3"; resume_ranks="$4"; mode="$5"
interval="$6"; stop="$7"; shift 7
scenes=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do scenes+=("$(realpath "$1")"); shift; done
shift
mpiexec="$1"; np_flag="$2"; shift 2
preflags=("$@")

run() {
  local ranks="$1"; shift
  if [ "$ranks" -eq 1 ]; then "$@"; else "$mpiexec" "$np_flag" "$ranks" "${preflags[@]}" "$@"; fi
}
fail() { echo "FAIL: $*"; exit 1; }

rm -rf "resume-$name"; mkdir -p "resume-$name"; cd "resume-$name" || exit 1
common='subsection Test\n set Enable = true\nend\nsubsection Timer\n set Type = none\nend\n'
printf "subsection Output\n set Directory = full\nend\n$common" > full.prm
printf "subsection Output\n set Directory = resumed\nend\nsubsection Checkpoint\n set Step interval = %s\nend\n$common" "$interval" > resumed.prm
printf 'subsection Time\n set Maximum number of steps = %s\nend\n' "$stop" > stop.prm

run "$full_ranks" "$fmpm" "${scenes[@]}" full.prm > full.log 2>&1 || { tail full.log; fail "uninterrupted run"; }

case "$mode" in
  steps)
    run "$full_ranks" "$fmpm" "${scenes[@]}" resumed.prm stop.prm > first.log 2>&1 \
      || { tail first.log; fail "first part"; }
    ;;
  signal)
    FMPM_TEST_SIGNAL_AT_STEP="$stop" run "$full_ranks" "$fmpm" "${scenes[@]}" resumed.prm > first.log 2>&1
    code=$?
    [ "$code" -eq 3 ] || { tail first.log; fail "exit code $code after the signal, expected 3"; }
    grep -q '"status": "stopped: signal"' resumed/summary.json || fail "summary.json status is not 'stopped: signal'"
    [ -d "resumed/checkpoint/$(printf 'step-%06d' "$stop")" ] || fail "no checkpoint at the signal's step $stop"
    ;;
  kill)
    FMPM_TEST_STOP_DURING_CHECKPOINT="$stop" run "$full_ranks" "$fmpm" "${scenes[@]}" resumed.prm > first.log 2>&1
    code=$?
    [ "$code" -ne 0 ] || fail "the run did not die during the checkpoint"
    [ -d "resumed/checkpoint/$(printf 'step-%06d.tmp' "$stop")" ] || fail "no temporary checkpoint of step $stop"
    [ -d "resumed/checkpoint/$(printf 'step-%06d' "$stop")" ] && fail "the interrupted checkpoint of step $stop looks complete"
    ;;
  *) fail "unknown mode $mode" ;;
esac

run "$resume_ranks" "$fmpm" --resume "${scenes[@]}" resumed.prm > resume.log 2>&1 \
  || { tail resume.log; fail "resumed run"; }
grep -q "resumed from" resume.log || fail "the resumed run does not say where it resumed from"
if [ "$mode" = kill ]; then
  grep -q "$(printf 'step-%06d' "$((stop - interval))") at step $((stop - interval))" resume.log \
    || { grep "resumed from" resume.log; fail "did not resume from the previous checkpoint (step $((stop - interval)))"; }
fi
grep -q '"status": "completed"' resumed/summary.json || fail "resumed run not completed"

# The physics of summary.json: without wall times, memory and (other rank counts)
# the partition and the CG iteration counts (a sum in another order can stop
# an iteration earlier or later).
physics() {
  sed '/"phase_wall_seconds"/,$d' "$1" | grep -v -e wall_seconds -e particle_steps_per_second -e resident_bytes -e support_cache_bytes -e latest_checkpoint \
    | if [ "$full_ranks" = "$resume_ranks" ]; then cat; else grep -v -e n_mpi_ranks -e point_imbalance -e cg_iterations; fi
}
physics full/summary.json > full.summary
physics resumed/summary.json > resumed.summary
sed -n '/^points (id/,$p' full.log > full.points
sed -n '/^points (id/,$p' resume.log > resumed.points
[ -s full.points ] || fail "no point output"

if [ "$full_ranks" = "$resume_ranks" ]; then
  cmp full/history.csv resumed/history.csv || { diff full/history.csv resumed/history.csv | head; fail "history.csv differs"; }
  cmp full.summary resumed.summary || { diff full.summary resumed.summary; fail "summary.json differs"; }
  cmp full.points resumed.points || { diff full.points resumed.points | head; fail "points differ"; }
  # Every particle VTU file (grid VTU files list the cells in the mesh's
  # storage order, which differs after adaptations; without the line with the time of writing).
  for vtu in full/particles_*.vtu; do
    [ -e "$vtu" ] || continue
    cmp <(grep -av '^#This file was generated' "$vtu") \
        <(grep -av '^#This file was generated' "resumed/$(basename "$vtu")") \
      || fail "$(basename "$vtu") differs"
  done
  if [ -e full/particles.pvd ]; then
    cmp <(grep -av '^#This file was generated' full/particles.pvd) \
        <(grep -av '^#This file was generated' resumed/particles.pvd) || fail "particles.pvd differs"
  fi
else
  [ "$(wc -l < full/history.csv)" = "$(wc -l < resumed/history.csv)" ] || fail "history.csv row counts differ"
  # (the points are printed with 9 digits: the last may round differently)
  for check in "full/history.csv resumed/history.csv 1e-9" "full.summary resumed.summary 1e-9" \
               "full.points resumed.points 1e-7"; do
    set -- $check
    numdiff -q -r "$3" -a 1e-10 -s ', \n:' "$1" "$2" \
      || { numdiff -r "$3" -a 1e-10 -s ', \n:' "$1" "$2" | head -20; fail "$1 and $2 differ beyond round-off"; }
  done
fi
echo PASS
