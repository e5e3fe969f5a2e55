#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# What writes checkpoints besides 'Step interval': 'Wall time interval'
# (with 'Keep'), and a real SIGTERM from outside, after which the run stops
# cleanly (exit code 3, summary.json status "stopped: signal") and resumes.
#
#   check_checkpoint_triggers.sh FMPM SOURCE_DIR
set -u
fmpm="$1"; source_dir="$2"
disks="$source_dir/../../parameters/colliding_disks.prm"
fail() { echo "FAIL: $*"; exit 1; }
rm -rf checkpoint-triggers; mkdir checkpoint-triggers; cd checkpoint-triggers || exit 1

# A wall-time interval shorter than a step: a checkpoint after every step,
# the newest 3 kept.
printf 'subsection Output\n set Directory = wall\n set Write vtu = false\nend\nsubsection Time\n set Maximum number of steps = 6\nend\nsubsection Checkpoint\n set Wall time interval = 1e-9\n set Keep = 3\nend\nsubsection Timer\n set Type = none\nend\n' > wall.prm
"$fmpm" "$disks" wall.prm > wall.log 2>&1
code=$?
[ "$code" -eq 0 ] || { tail wall.log; fail "run with a wall-time interval: exit code $code"; }
[ "$(ls wall/checkpoint)" = "$(printf 'step-000004\nstep-000005\nstep-000006')" ] \
  || { ls wall/checkpoint; fail "expected the checkpoints of steps 4, 5, 6"; }

# SIGTERM from outside while the run is stepping.
printf 'subsection Output\n set Directory = signal\n set Write vtu = false\n set Interval = 0.01\nend\nsubsection Time\n set End time = 1000\nend\nsubsection Timer\n set Type = none\nend\n' > signal.prm
"$fmpm" "$disks" signal.prm > signal.log 2>&1 &
pid=$!
for _ in $(seq 1 300); do
  [ -f signal/history.csv ] && [ "$(wc -l < signal/history.csv)" -ge 4 ] && break
  sleep 0.1
done
kill -TERM "$pid"
wait "$pid"
code=$?
[ "$code" -eq 3 ] || { tail signal.log; fail "exit code $code after SIGTERM, expected 3"; }
grep -q '"status": "stopped: signal"' signal/summary.json || fail "summary.json status is not 'stopped: signal'"
grep -q "Stopped by a signal at step" signal.log || fail "no message about the stop"
ls -d signal/checkpoint/step-* > /dev/null 2>&1 || fail "no checkpoint after SIGTERM"
rows=$(wc -l < signal/history.csv)
# The resumed run continues (stopped again after 5 more steps).
printf 'subsection Time\n set Maximum number of steps = %s\nend\n' \
  "$(( $(ls -d signal/checkpoint/step-* | tail -1 | sed 's/.*step-0*//') + 5 ))" > more.prm
"$fmpm" --resume "$disks" signal.prm more.prm > resume.log 2>&1 || { tail resume.log; fail "resume after SIGTERM"; }
grep -q '"status": "stopped: step limit"' signal/summary.json || fail "the resumed run did not stop at its step limit"
[ "$(wc -l < signal/history.csv)" -ge "$rows" ] || fail "history.csv lost rows"
echo PASS
