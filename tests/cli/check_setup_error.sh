#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# An error found while setting up a run stops it with exit code 1 and one
# message, and no TimerOutput summary is printed (neither before the
# message, as it was from the Simulator's destructor during stack
# unwinding, nor after it).
#   check_setup_error.sh TEXT -- COMMAND...
set -u
text="$1"; shift 2
output="$("$@" 2>&1)"
code=$?
echo "$output" | tail -n 30
[ "$code" -eq 1 ] || { echo "FAIL: exit code $code, expected 1"; exit 1; }
n="$(echo "$output" | grep -F -c -- "$text")"
[ "$n" -eq 1 ] || { echo "FAIL: '$text' appears $n times, expected 1"; exit 1; }
if echo "$output" | grep -q -i "wallclock"; then
  echo "FAIL: the timing table is printed"; exit 1
fi
echo "PASS"
