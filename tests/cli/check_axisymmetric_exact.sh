#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# Axisymmetric exact checks (Geometry = axisymmetric) on
# scenes/axisymmetric_cylinder.prm, every node held at v_r = a r, v_z = b z,
# for each shape function (classic, ugimp, cpgimp, cpdi, and the B-splines
# b2spline, b3spline, b2gimp, b2cpdi with open knots at the axis):
#  (a) uniform axial compression (a = -nu b), linear elastic 'total':
#      F_rr = F_tt = c_a^N, F_zz = c_b^N (N Cayley steps,
#      c = (1 + x dt/2)/(1 - x dt/2)), sigma = C : (F - I): sigma_rr,
#      sigma_zz, sigma_tt of every point to 1e-11 of |sigma_zz|; the strain
#      energy (per radian, W per initial volume) W R^2 H / 2 and the mass
#      rho R^2 H / 2 to 1e-10;
#  (b) uniform radial displacement (the Lame state of a solid cylinder,
#      b = 0), linear elastic 'incremental': sigma_rr = sigma_tt =
#      2 (lambda + mu) a N dt, sigma_zz = 2 lambda a N dt to 1e-11.
# A missing hoop rate (L_33 = 0) or volume per radian fails both.
#   check_axisymmetric_exact.sh FMPM SOURCE_DIR [MPIEXEC ...]
set -u
fmpm="$1"; source_dir="$2"; shift 2
launcher=("$@")
scene="$source_dir/scenes/axisymmetric_cylinder.prm"
status=0
run_case() {
  local name="$1" shape="$2" a="$3" b="$4" measure="$5"
  local dir="output-axisymmetric-$name-$shape"
  # (B-splines: 6 x 12 cells, so that the cubic basis with open knots, at
  # least 2 p = 6 cells per direction, is cubic in r.)
  local subdivisions="4, 8"
  case "$shape" in b*) subdivisions="6, 12" ;; esac
  printf 'subsection Mesh\n set Subdivisions = %s\nend\nsubsection Shape function\n set Type = %s\nend\nsubsection Boundary conditions\n subsection Moving wall 0\n  set Function constants = a=%s\n end\n subsection Moving wall 1\n  set Function constants = b=%s\n end\nend\nsubsection Material 0\n subsection Linear elastic\n  set Strain measure = %s\n end\nend\nsubsection Output\n set Directory = %s\nend\n' \
    "$subdivisions" "$shape" "$a" "$b" "$measure" "$dir" > "$dir.prm"
  if ! "${launcher[@]}" "$fmpm" "$scene" "$dir.prm" > "$dir.log" 2>&1; then
    echo "FAIL: $name $shape did not run"; cat "$dir.log"; status=1; return
  fi
  python3 - "$dir" "$a" "$b" "$measure" "$name $shape" <<'PY' || status=1
import csv, glob, sys
directory, a, b, measure, label = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), sys.argv[4], sys.argv[5]
E, nu, rho, R, H = 1e6, 0.3, 1000., 1., 2.
lam, mu = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
with open(directory + "/history.csv") as f:
    lines = [l for l in f if not l.startswith("#")]
rows = list(csv.DictReader(lines))
last = rows[-1]
N, dt = int(last["step"]), float(rows[1]["dt"])
if measure == "total":
    c = lambda x: (1 + 0.5 * x * dt) / (1 - 0.5 * x * dt)
    e_r, e_z = c(a) ** N - 1, c(b) ** N - 1
else:
    e_r, e_z = a * N * dt, b * N * dt
tr = 2 * e_r + e_z
s_rr, s_zz = lam * tr + 2 * mu * e_r, lam * tr + 2 * mu * e_z
scale = max(abs(s_rr), abs(s_zz))
with open(sorted(glob.glob(directory + "/particles_*.csv"))[-1]) as f:
    points = list(csv.DictReader(f))
error = 0.
for p in points:
    error = max(error, abs(float(p["stress_xx"]) - s_rr), abs(float(p["stress_hoop"]) - s_rr),
                abs(float(p["stress_yy"]) - s_zz), abs(float(p["stress_xy"])))
ok = error <= 1e-11 * scale
print(f"{label}: {len(points)} points, N = {N}, sigma_rr = sigma_tt = {s_rr:.9g}, sigma_zz = {s_zz:.9g}, "
      f"largest error {error:.3g} ({error / scale:.2g} of the scale)")
mass = float(last["mass"])
mass_error = abs(mass - rho * R * R * H / 2) / (rho * R * R * H / 2)
print(f"  mass per radian {mass:.12g}, relative error {mass_error:.2g}")
ok = ok and mass_error < 1e-10
if measure == "total":
    W = 0.5 * (s_rr * e_r * 2 + s_zz * e_z)
    expected = W * R * R * H / 2
    energy_error = abs(float(last["strain_energy"]) - expected) / abs(expected)
    print(f"  strain energy per radian {float(last['strain_energy']):.12g}, exact {expected:.12g}, relative error {energy_error:.2g}")
    ok = ok and energy_error < 1e-10
if not ok:
    print("FAIL:", label)
sys.exit(0 if ok else 1)
PY
}
for shape in classic ugimp cpgimp cpdi b2spline b3spline b2gimp b2cpdi; do
  run_case axial "$shape" 0.06 -0.2 total
  run_case radial "$shape" 0.1 0 incremental
done
[ "$status" -eq 0 ] && echo PASS
exit "$status"
