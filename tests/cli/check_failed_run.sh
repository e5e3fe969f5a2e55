#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# A numerically failing run exits with code 2, reports step, time and the
# offending point, and leaves summary.json (status failed) and history.csv.
set -u
fmpm="$1"; source_dir="$2"
rm -rf output-blow-up
"$fmpm" "$source_dir/../../parameters/vibrating_bar.prm" "$source_dir/scenes/blow_up.prm" > log.txt 2>&1
code=$?
cat log.txt | tail -5
[ "$code" -eq 2 ] || { echo "FAIL: exit code $code, expected 2"; exit 1; }
grep -q "The run failed at step" log.txt || { echo "FAIL: no failure message"; exit 1; }
grep -q '"status": "failed: ' output-blow-up/summary.json || { echo "FAIL: summary.json"; exit 1; }
grep -q '"failure_step"' output-blow-up/summary.json || { echo "FAIL: no failure_step"; exit 1; }
[ "$(wc -l < output-blow-up/history.csv)" -ge 2 ] || { echo "FAIL: history.csv lost"; exit 1; }
echo PASS
