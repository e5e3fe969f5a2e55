#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Copyright (C) 2026 by the fmpm authors
#
# Runs every shipped scene (parameters/*.prm) on one rank, one after the
# other, and prints the share of the wall time (from set-up to the summary)
# that the TimerOutput sections cover, with the steps and the wall time of
# the sections' window (summary.json: timer_coverage, steps, wall_seconds):
#
#   contrib/utilities/timer_coverage.sh [FMPM]
#
# FMPM defaults to build/applications/fmpm/fmpm. Environment:
#   SCENES      the scene files [parameters/*.prm]
#   MAX_STEPS   if set, 'Time/Maximum number of steps' of every scene whose
#               name starts with benchmark_ [unset: as shipped]
# Outputs go to a temporary folder, removed at the end.
set -eu
root="$(cd "$(dirname "$0")/../.." && pwd)"
fmpm="$(realpath "${1:-$root/build/applications/fmpm/fmpm}")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
field() { # field NAME summary.json
  sed -n "s/^ *\"$1\": *\([^,]*\),*$/\1/p" "$2" | head -n 1
}
printf '| scene | status | steps | wall s | coverage %% |\n|---|---|---:|---:|---:|\n'
for prm in ${SCENES:-"$root"/parameters/*.prm}; do
  prm="$(realpath "$prm")"
  name="$(basename "$prm" .prm)"
  override="$work/$name.prm"
  printf 'subsection Output\n  set Directory = %s\nend\n' "$work/$name" > "$override"
  case "$name" in
    benchmark_*) if [ -n "${MAX_STEPS:-}" ]; then
        printf 'subsection Time\n  set Maximum number of steps = %s\nend\n' \
          "$MAX_STEPS" >> "$override"
      fi ;;
  esac
  (cd "$(dirname "$prm")" && "$fmpm" "$prm" "$override" > "$work/$name.log" 2>&1) || true
  summary="$work/$name/summary.json"
  if [ -f "$summary" ]; then
    coverage="$(field timer_coverage "$summary")"
    printf '| %s | %s | %s | %.3g | %.1f |\n' "$name" "$(field status "$summary" | tr -d '"' | cut -c1-20)" \
      "$(field n_steps "$summary")" "$(field wall_seconds "$summary")" \
      "$(echo "100 * $coverage" | bc -l)"
  else
    printf '| %s | no summary: %s | | | |\n' "$name" "$(tail -n 1 "$work/$name.log")"
  fi
done
