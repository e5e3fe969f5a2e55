#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# An error found while setting up a run stops it with exit code 1 and one
# message, and no TimerOutput summary is printed (neither before the
# message, as it was from the Simulator's destructor during stack
# unwinding, nor after it). The files of an earlier run in the scene's
# output directory stay where they are.
#   check_setup_error.sh TEXT OUTPUT_DIRECTORY -- COMMAND...
set -u
text="$1"; directory="$2"; shift 3
rm -rf "$directory"
mkdir -p "$directory"
echo "time,earlier run" > "$directory/history.csv"
output="$("$@" 2>&1)"
code=$?
echo "$output" | tail -n 30
[ "$code" -eq 1 ] || { echo "FAIL: exit code $code, expected 1"; exit 1; }
n="$(echo "$output" | grep -F -c -- "$text")"
[ "$n" -eq 1 ] || { echo "FAIL: '$text' appears $n times, expected 1"; exit 1; }
if echo "$output" | grep -q -i "wallclock"; then
  echo "FAIL: the timing table is printed"; exit 1
fi
grep -q "earlier run" "$directory/history.csv" 2>/dev/null ||
  { echo "FAIL: the earlier run's history.csv was moved or overwritten"; exit 1; }
[ ! -e "$directory/previous_run" ] ||
  { echo "FAIL: a refused scene set the earlier run aside"; exit 1; }
echo "PASS"
