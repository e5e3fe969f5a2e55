#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# What a run leaves in its output directory can be trusted:
#  1. summary.json's energy_error is the balance (E - E0 - W)/scale with the
#     work W of walls and tractions: a piston that does work on a bar
#     (the run-time check's balance is about 1e-4) reports a small error,
#     not 1.
#  2. A run stopped by Time/Maximum number of steps writes its last step
#     (history.csv) and says so in summary.json ("stopped: step limit").
#  3. A new run in the directory of an earlier, longer one leaves none of
#     the earlier run's files next to its own: they move to previous_run/.
#  4. FMPM(16) with an increment tolerance (adaptive order) reports the
#     order it used in history.csv and summary.json.
#
#   check_run_outputs.sh FMPM SOURCE_DIR
set -u
fmpm="$1"; source_dir="$2"
root="$source_dir/../.."
fail() { echo "FAIL: $*"; exit 1; }
rm -rf run-outputs; mkdir run-outputs; cd run-outputs || exit 1
common='subsection Timer\n set Type = none\nend\n'

# 1. Energy balance with external work.
printf "subsection Output\n set Directory = piston\n set Write vtu = false\nend\nsubsection Time\n set End time = 0.15\nend\n$common" > piston.prm
"$fmpm" "$root/parameters/piston.prm" piston.prm > piston.log 2>&1 || { tail piston.log; fail "piston run"; }
python3 - piston/summary.json <<'PY' || fail "energy_error of the piston run"
import json, sys
s = json.load(open(sys.argv[1]))
work, error = s["external_work"], s["energy_error"]
balance = s["final_total_energy"] - s["initial_total_energy"] - work
print(f"external work {work:.6g}, balance {balance:.3g}, energy_error {error:.3g}")
# The piston does work; the error is the balance, small against it.
sys.exit(0 if work > 0 and abs(error) < 1e-2 and abs(balance) < 1e-2 * work else 1)
PY

# 2. The step limit.
printf "subsection Output\n set Directory = limited\n set Write vtu = false\n set Interval = 0\n set Step interval = 4\nend\nsubsection Time\n set Maximum number of steps = 10\nend\n$common" > limited.prm
"$fmpm" "$root/parameters/colliding_disks.prm" limited.prm > limited.log 2>&1 || { tail limited.log; fail "step-limited run"; }
last=$(tail -1 limited/history.csv | cut -d, -f1)
[ "$last" = 10 ] || fail "the last history.csv row is step $last, not the last step 10"
grep -q '"status": "stopped: step limit"' limited/summary.json || { grep status limited/summary.json; fail "status of a step-limited run"; }
grep -q "Maximum number of steps = 10" limited.log || fail "no message about the step limit"

# 3. A shorter run after a longer one in the same directory.
printf "subsection Output\n set Directory = reused\n set Interval = 0.02\nend\nsubsection Time\n set End time = %s\nend\n$common" 0.2 > long.prm
printf "subsection Output\n set Directory = reused\n set Interval = 0.02\nend\nsubsection Time\n set End time = %s\nend\n$common" 0.06 > short.prm
"$fmpm" "$root/parameters/colliding_disks.prm" long.prm > long.log 2>&1 || { tail long.log; fail "long run"; }
"$fmpm" "$root/parameters/colliding_disks.prm" short.prm > short.log 2>&1 || { tail short.log; fail "short run"; }
listed=$(grep -c 'file=' reused/particles.pvd)
present=$(ls reused/particles_*.pvtu | wc -l)
[ "$listed" = "$present" ] || fail "particles.pvd lists $listed outputs, the directory holds $present"
[ "$(ls reused/previous_run/particles_*.pvtu | wc -l)" -gt "$present" ] || fail "the earlier run's files are not in previous_run/"
grep -q "moved the .* files of an earlier run" short.log || fail "no message about the earlier run's files"
# 4. The adaptive order reports the order it used.
printf "subsection Output\n set Directory = adaptive\n set Write vtu = false\nend\nsubsection Time\n set End time = 0.5\nend\nsubsection Particle update\n set Model name = fmpm\nend\nsubsection Mass matrix\n set Model name = fmpm\n subsection Fmpm\n  set Order = 16\n  set Increment tolerance = 1e-3\n end\nend\n$common" > adaptive.prm
"$fmpm" "$root/parameters/colliding_disks.prm" adaptive.prm > adaptive.log 2>&1 || { tail adaptive.log; fail "adaptive-order run"; }
python3 - adaptive/history.csv adaptive/summary.json <<'PY' || fail "the adaptive order's history columns"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
means = [float(r["fmpm_order_mean"]) for r in rows[1:]]
maxima = [float(r["fmpm_order_max"]) for r in rows[1:]]
summary = json.load(open(sys.argv[2]))
print(f"order mean {min(means):.3g}-{max(means):.3g}, max {max(maxima):g}, run mean {summary['fmpm_order_mean']:.3g}")
ok = all(1 < m <= x <= 16 for m, x in zip(means, maxima)) and summary["fmpm_order_max"] == max(maxima)
sys.exit(0 if ok else 1)
PY
echo PASS
