#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Serial runs started at the same moment must all start: 32 streams of
# 6 `fmpm --version` each (MPI_Init and MPI_Finalize of 192 serial runs,
# overlapping). With one run-time folder shared by all serial runs, 4 to 6
# of the 192 failed in MPI_Init on two cores.
set -u
fmpm="$1"; streams=${2:-32}; starts=${3:-6}
work=$(mktemp -d)
for s in $(seq 1 "$streams"); do
  (
    failures=0
    for i in $(seq 1 "$starts"); do
      "$fmpm" --version > /dev/null 2> "$work/err.$s" || {
        failures=$((failures + 1)); cp "$work/err.$s" "$work/failed.$s"; }
    done
    echo "$failures" > "$work/count.$s"
  ) &
done
wait
total=$(cat "$work"/count.* | awk '{s += $1} END {print s}')
echo "$total of $((streams * starts)) serial starts failed"
if [ "$total" -ne 0 ]; then
  head -12 "$(ls "$work"/failed.* | head -1)"
  rm -rf "$work"; echo FAIL; exit 1
fi
rm -rf "$work"; echo PASS
