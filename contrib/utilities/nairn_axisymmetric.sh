# SPDX-License-Identifier: LGPL-2.1-or-later
# Shared by the axisymmetric NairnMPM twins (nairn_axial_cylinder.sh, nairn_radial_disk.sh), sourced
# after nairn_common.sh with SHAPE, CFL, tmax, E, nu, rho set:
#   m EXPR                                   prints an awk arithmetic expression to 10 digits
#   nairn_axi_head DESCRIPTION ARCHIVE_ROOT  prints the XML from its declaration to </MPMHeader>:
#                                            axisymmetric (Analysis 13), mm-g-ms, USAVG+, 2x2 points
#                                            per cell, one archive at tmax, 200 global archives of
#                                            sxx, syy, szz (sigma_rr, sigma_zz, sigma_thetatheta)
#   nairn_axi_material NAME                  prints the linear elastic <Material>
#   nairn_axi_report TITLE SRR SZZ STT       after nairn_run: prints points, steps, wall time,
#                                            particle-steps/s, the run's own wall time (Elapsed Time
#                                            per Step of output.txt times steps) and, per stress,
#                                            its exact value (MPa),
#                                            its value at the end and its mean over the last tenth
#                                            of the run, with relative errors, also against
#                                            J sigma_exact (J = 1 + tr(eps) of the exact strains)

m() { awk "BEGIN{printf \"%.10g\", $*}"; }

nairn_axi_head() {
  cat <<X
<?xml version='1.0'?>
<!DOCTYPE JANFEAInput SYSTEM "NairnMPM.dtd">
<JANFEAInput version='3'>
  <Header><Description>$1</Description><Analysis>13</Analysis>
    <ConsistentUnits length="mm" mass="g" time="ms"/></Header>
  <MPMHeader>
    <MPMMethod>2</MPMMethod>
    <GIMP type="$SHAPE"/>
    <MatlPtsPerElement>4</MatlPtsPerElement>
    <Timing CFL="$CFL"/>
    <MaxTime>$tmax</MaxTime>
    <ArchiveTime>$tmax</ArchiveTime>
    <ArchiveRoot>$2</ArchiveRoot>
    <MPMArchiveOrder>iYYYNNNNNNNNNNNNNN</MPMArchiveOrder>
    <GlobalArchiveTime>$(m "$tmax/200")</GlobalArchiveTime>
    <GlobalArchive type="sxx"/>
    <GlobalArchive type="syy"/>
    <GlobalArchive type="szz"/>
  </MPMHeader>
X
}

nairn_axi_material() {
  echo "  <Material Type=\"1\" Name=\"$1\"><rho>$rho</rho><E>$E</E><nu>$nu</nu><alpha>0</alpha></Material>"
}

nairn_axi_report() {
  PYTHONPATH="$here" python3 - "$1" "$SHAPE" "$np" "$nairn_wall" "$2" "$3" "$4" "$nu" "$E" <<'PY'
import sys
import nairn_results
title, shape, np_, wall = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4])
srr, szz, stt, nu, E = map(float, sys.argv[5:10])
steps, npts, rows, col = nairn_results.load()
exact = {'sxx': srr, 'syy': szz, 'szz': stt}
label = {'sxx': 'sigma_rr', 'syy': 'sigma_zz', 'szz': 'sigma_thetatheta'}
# J = 1 + tr(eps) from the exact strains.
J = 1 + (1 - 2 * nu) / E * sum(exact.values())
tail = rows[-max(1, len(rows) // 10):]
import re
with open('output.txt') as f:
    per_step = re.search(r'Elapsed Time per Step: ([0-9.e+-]+) ms', f.read())
steps_wall = float(per_step.group(1)) * 1e-3 * steps if per_step else float('nan')
print(f'NairnMPM {title} {shape} threads={np_} points={npts} steps={steps} wall_s={wall:.2f} '
      f'steps_wall_s={steps_wall:.3f} particle_steps_per_s={npts*steps/wall:.3g}')
for q in ('sxx', 'syy', 'szz'):
    end, mean = rows[-1][col[q]], sum(r[col[q]] for r in tail) / len(tail)
    print(f'  {label[q]}: exact={exact[q]:.6g} end={end:.6g} ({end/exact[q]-1:+.2e}) '
          f'mean_last_tenth={mean:.6g} ({mean/exact[q]-1:+.2e}; against J sigma_exact {mean/(J*exact[q])-1:+.2e})')
PY
}
