#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Run a command and check its exit code and output.
#   expect.sh EXIT_CODE TEXT COUNT -- COMMAND...
# passes if COMMAND exits with EXIT_CODE and TEXT appears exactly COUNT times
# in its combined output (COUNT 0 skips the count check but TEXT must
# appear; an empty TEXT skips the text check). A crash (signal, core dump,
# 'terminate called') always fails.
set -u
expected_exit="$1"; text="$2"; count="$3"; shift 4
output="$("$@" 2>&1)"
code=$?
echo "$output" | tail -n 30
if [ "$code" -ge 128 ] || echo "$output" | grep -q -E "terminate called|Segmentation fault|core dumped|Aborted"; then
  echo "FAIL: the command crashed (exit $code)"; exit 1
fi
if [ "$code" -ne "$expected_exit" ]; then
  echo "FAIL: exit code $code, expected $expected_exit"; exit 1
fi
if [ -n "$text" ]; then
  n="$(echo "$output" | grep -F -c -- "$text")"
  if [ "$n" -eq 0 ] || { [ "$count" -gt 0 ] && [ "$n" -ne "$count" ]; }; then
    echo "FAIL: '$text' appears $n times, expected ${count/#0/at least 1}"; exit 1
  fi
fi
echo "PASS"
