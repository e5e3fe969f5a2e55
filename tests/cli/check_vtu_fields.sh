#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# The particle VTU as ParaView reads it: velocity a 3-component vector,
# stress and deformation_gradient 9-component tensors (plus their zz
# components in 2D), compressed or not (Output/Compression), and the
# grid velocity one vector. The values agree, point by point (by id),
# with particles_NNNNN.csv, to Float32 precision: the tensor's XX, XY,
# YY entries are sigma_xx, sigma_xy, sigma_yy; det F = J.
#
#   check_vtu_fields.sh FMPM SCENE UTILITIES_DIR
set -u
fmpm="$1"; scene="$(realpath "$2")"; utilities="$(realpath "$3")"
fail() { echo "FAIL: $*"; exit 1; }
rm -rf vtu-fields; mkdir vtu-fields; cd vtu-fields || exit 1
for compression in "best speed" none; do
  dir="out-${compression// /-}"
  printf 'subsection Output\n set Directory = %s\n set Interval = 0.5\n set Write particle csv = true\n set Compression = %s\nend\nsubsection Time\n set End time = 1.5\nend\nsubsection Timer\n set Type = none\nend\n' "$dir" "$compression" > "$dir.prm"
  "$fmpm" "$scene" "$dir.prm" > "$dir.log" 2>&1 || { tail "$dir.log"; fail "run ($compression)"; }
  grep -q 'Name="velocity" NumberOfComponents="3"' "$dir"/grid_00003.0.vtu || fail "grid velocity is not one vector ($compression)"
  python3 - "$utilities" "$dir" <<'PY' || fail "VTU fields differ from the csv ($compression)"
import csv, sys
sys.path.insert(0, sys.argv[1])
import fmpm_vtu
directory = sys.argv[2]
content = open(directory + "/particles_00003.0.vtu").read()
for name, n in (("velocity", 3), ("stress", 9), ("deformation_gradient", 9)):
    if 'Name="%s" NumberOfComponents="%d"' % (name, n) not in content:
        sys.exit("no %d-component %s" % (n, name))
fields = ["id", "velocity:0", "velocity:1", "stress:0", "stress:1", "stress:3",
          "stress:4", "stress:8", "stress_zz", "deformation_gradient:0",
          "deformation_gradient:1", "deformation_gradient:3",
          "deformation_gradient:4", "deformation_gradient_zz"]
time, x, y, z, v = fmpm_vtu.read_output(directory, 1.0, fields)
rows = {int(r["id"]): r for r in csv.DictReader(open(directory + "/particles_00002.csv"))}
if abs(time - 1.0) > 0.05 or len(rows) != len(x):
    sys.exit("output at t = %g with %d points, csv %d rows" % (time, len(x), len(rows)))
scale = max(abs(float(r["stress_xx"])) for r in rows.values())
worst = 0
for i in range(len(x)):
    r = rows[int(v["id"][i])]
    F = [v["deformation_gradient:%d" % c][i] for c in (0, 1, 3, 4)]
    J = (F[0] * F[3] - F[1] * F[2]) * v["deformation_gradient_zz"][i]
    checks = [(v["velocity:0"][i], float(r["vx"]), 1e-6),
              (v["velocity:1"][i], float(r["vy"]), 1e-6),
              (x[i], float(r["x"]), 1e-6), (y[i], float(r["y"]), 1e-6),
              (v["stress:0"][i], float(r["stress_xx"]), 1e-6 * scale),
              (v["stress:1"][i], float(r["stress_xy"]), 1e-6 * scale),
              (v["stress:3"][i], float(r["stress_xy"]), 1e-6 * scale),
              (v["stress:4"][i], float(r["stress_yy"]), 1e-6 * scale),
              (v["stress:8"][i], 0.0, 0.0),
              (J, float(r["J"]), 1e-5)]
    for got, want, tolerance in checks:
        worst = max(worst, abs(got - want) - tolerance)
    # sigma_zz of plane strain: -p from the trace, p = -(xx + yy + zz)/3
    zz = -3 * float(r["pressure"]) - float(r["stress_xx"]) - float(r["stress_yy"])
    worst = max(worst, abs(v["stress_zz"][i] - zz) - 1e-5 * scale)
if worst > 0:
    sys.exit("largest excess over the tolerance %g" % worst)
print("%s: %d points agree with the csv" % (directory, len(x)))
PY
done
echo PASS
