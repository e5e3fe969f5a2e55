#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# A stop by signal on 2 ranks under mpirun/mpiexec.
#  - SIGUSR1 to mpiexec (Open MPI forwards it to every rank): the run writes
#    a checkpoint, summary.json ("stopped: signal", naming the checkpoint)
#    and the message, exits 3, and resumes from that checkpoint.
#  - SIGINT to mpiexec (Ctrl-C): Open MPI's mpiexec sends SIGTERM to the
#    ranks and kills them a second later, and exits with its own code; the
#    ranks write summary.json and the message first.
#
#   check_mpi_signal.sh FMPM SCENE -- MPIEXEC NP_FLAG [PREFLAGS...]
set -u
fmpm="$1"; scene="$(realpath "$2")"; shift 3
mpiexec=("$1" "$2" 2); shift 2
mpiexec+=("$@")
fail() { echo "FAIL: $*"; exit 1; }
rm -rf mpi-signal; mkdir mpi-signal; cd mpi-signal || exit 1

start() { # start DIR: a long 2-rank run in the background, once it steps
  printf 'subsection Output\n set Directory = %s\n set Write vtu = false\n set Interval = 0.01\nend\nsubsection Time\n set End time = 1000\nend\nsubsection Timer\n set Type = none\nend\n' "$1" > "$1.prm"
  "${mpiexec[@]}" "$fmpm" "$scene" "$1.prm" > "$1.log" 2>&1 &
  pid=$!
  for _ in $(seq 1 600); do
    [ -f "$1/history.csv" ] && [ "$(wc -l < "$1/history.csv")" -ge 4 ] && break
    sleep 0.1
  done
}

start usr1
kill -USR1 "$pid"
wait "$pid"
code=$?
[ "$code" -eq 3 ] || { tail usr1.log; fail "exit code $code after SIGUSR1, expected 3"; }
grep -q '"status": "stopped: signal"' usr1/summary.json || fail "SIGUSR1: summary.json status is not 'stopped: signal'"
grep -q "Stopped by a signal at step" usr1.log || fail "SIGUSR1: no message about the stop"
checkpoint=$(sed -n 's/.*"latest_checkpoint": "\(.*\)".*/\1/p' usr1/summary.json)
[ -n "$checkpoint" ] && [ -f "$checkpoint/state.bin" ] || fail "SIGUSR1: summary.json names no complete checkpoint ($checkpoint)"
ls -d usr1/checkpoint/*.tmp > /dev/null 2>&1 && fail "SIGUSR1: an unfinished checkpoint is left"
step=$(basename "$checkpoint" | sed 's/step-0*//')
printf 'subsection Time\n set Maximum number of steps = %s\nend\n' "$((step + 5))" > more.prm
"${mpiexec[@]}" "$fmpm" --resume "$scene" usr1.prm more.prm > resume.log 2>&1 || { tail resume.log; fail "resume after SIGUSR1"; }
grep -q "resumed from" resume.log || fail "the resumed run does not say where it resumed from"

start sigint
kill -INT "$pid"
wait "$pid"
code=$?
[ "$code" -ne 0 ] || fail "SIGINT: exit code 0"
grep -q '"status": "stopped: signal"' sigint/summary.json || { tail sigint.log; fail "SIGINT: summary.json status is not 'stopped: signal'"; }
grep -q "Stopped by a signal at step" sigint.log || fail "SIGINT: no message about the stop"
echo PASS
