#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Output/Tracked points: a block translating at v = (0.5, 0.25) m/s. The
# tracked points' columns of history.csv hold u = v t, the velocity v and
# zero stress at every row (at the exact output times), the same bits on 1
# and 2 MPI ranks; a position outside every body is refused, naming it.
#   check_tracked_points.sh FMPM SOURCE_DIR MPIEXEC...
set -u
fmpm="$1"; source_dir="$2"; shift 2
mpiexec=("$@")
scene="$source_dir/scenes/tracked_block.prm"
fail() { echo "FAIL: $*"; exit 1; }
for ranks in 1 2; do
  rm -rf "output-tracked-$ranks"
  printf 'subsection Output\n set Directory = output-tracked-%s\nend\n' "$ranks" > "tracked-$ranks.prm"
done
"$fmpm" "$scene" tracked-1.prm > tracked-1.log 2>&1 || { tail tracked-1.log; fail "serial run"; }
"${mpiexec[@]}" "$fmpm" "$scene" tracked-2.prm > tracked-2.log 2>&1 || { tail tracked-2.log; fail "2-rank run"; }
grep -q "2 MPI rank" tracked-2.log || fail "not on 2 ranks"
python3 - output-tracked-1/history.csv output-tracked-2/history.csv <<'PY' || fail "tracked point columns"
import csv, math, sys
one = list(csv.DictReader(open(sys.argv[1])))
two = list(csv.DictReader(open(sys.argv[2])))
columns = [c for c in one[0] if c.startswith("track")]
expected = [f"track{n}_{q}" for n in (1, 2) for q in
            ("ux", "uy", "vx", "vy", "sxx", "syy", "sxy")]
assert columns == expected, columns
assert len(one) == 11, len(one)
for a, b in zip(one, two):
    for c in columns:
        assert a[c] == b[c], (a["time"], c, a[c], b[c])  # same digits
for row in one:
    t = float(row["time"])
    assert abs(t / 0.05 - round(t / 0.05)) < 1e-9, t   # exact output times
    for n in (1, 2):
        ux, uy = float(row[f"track{n}_ux"]), float(row[f"track{n}_uy"])
        assert abs(ux - 0.5 * t) < 1e-12 and abs(uy - 0.25 * t) < 1e-12, (t, ux, uy)
        assert float(row[f"track{n}_vx"]) == 0.5 and float(row[f"track{n}_vy"]) == 0.25
        assert all(abs(float(row[f"track{n}_s{c}"])) < 1e-9 for c in ("xx", "yy", "xy"))
print("tracked points: u = v t at", len(one), "rows, 1 and 2 ranks agree")
PY
printf 'subsection Output\n set Directory = output-tracked-bad\n set Tracked points = 0.3, 0.3; 1.5, 0.5\nend\n' > tracked-bad.prm
output="$("$fmpm" "$scene" tracked-bad.prm 2>&1)"; code=$?
[ "$code" -eq 1 ] || { echo "$output" | tail; fail "exit code $code for a position outside every body"; }
echo "$output" | grep -q "Output/Tracked points = <0.3, 0.3; 1.5, 0.5>: the position (1.5 0.5) lies outside every body" \
  || { echo "$output" | tail; fail "no message naming the position outside every body"; }
echo PASS
