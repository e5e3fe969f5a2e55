#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Reproduces doc/studies/bsplines.md: the convergence runs (one progress line a
# run, one CSV row a run; resumable), the critical Courant numbers, then the
# charts and orders.csv. Runs at low priority.
# usage: bspline_study.sh [FMPM_BINARY]   (default build/applications/fmpm/fmpm)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd); repo=$(cd "$here/../.." && pwd)
fmpm=${1:-$repo/build/applications/fmpm/fmpm}
study="$repo/contrib/studies/bsplines/bsplines.py"
nice python3 "$study" run --fmpm "$fmpm"
nice python3 "$study" critical --fmpm "$fmpm"
python3 "$study" plot
