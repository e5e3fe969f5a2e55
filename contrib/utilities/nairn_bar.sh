#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of fmpm's parameters/nairn_bar.prm: runs NairnMPM on its mode-1 vibrating bar
# and prints one line: points, steps, wall time, particle-steps/s, max |mean velocity - exact|
# and E_end/E_0 (doc/benchmarks.md, "Against NairnMPM").
# Needs NairnMPM (github.com/nairnj/nairn-mpm-fea, built in NairnMPM/build with 'make SYSTEM=mpm');
# NAIRN names the binary (default ~/.nairn/bin/NairnMPM, or $NAIRN_DIR/bin); NairnMPM.dtd must sit beside it.
# usage: nairn_bar.sh VARIANT [THREADS]     VARIANT = FLIP | PIC | XPIC<k> | FMPM<k>
# env: NAIRN (binary, default $NAIRN_DIR/bin/NairnMPM), CELL (mm, default 2), SHAPE (uGIMP | lCPDI | Dirac | B2SPLINE | B2GIMP | B2CPDI),
#      MPMMETHOD (0 USF, 2 USAVG, 3 USL; default 2), SKIPPOST (1: USL-/USAVG-), CFL (default 0.5), NPER (periods, 2)
# The scene: L = 400 mm, H = 20 mm, E = 1000 MPa, nu = 0, rho = 1e-3 g/mm^3 (c = 1000 m/s, period 1.6 ms),
# plane stress, v0 = sin(pi x / 2L) m/s, grid velocity vx = 0 on x = 0, free at x = L, 2x2 points per cell,
# units mm-g-ms. Exact: mean velocity (2/pi) cos(w t), w = pi c / 2L; KE + SE = E_0.
set -euo pipefail
var=${1:?variant}; np=${2:-1}
here=$(cd "$(dirname "$0")" && pwd); source "$here/nairn_common.sh"
nairn_binary; nairn_task "$var" > /dev/null
CELL=${CELL:-2}; SHAPE=${SHAPE:-uGIMP}; MPMMETHOD=${MPMMETHOD:-2}; CFL=${CFL:-0.5}; NPER=${NPER:-2}
skip=""; [[ ${SKIPPOST:-0} == 1 ]] && skip="<SkipPostExtrapolation/>"
m() { awk "BEGIN{print $*}"; }
nairn_workdir nairnbar
L=400; H=20; tmax=$(m "1.6*$NPER")
cat > in.xml <<X
<?xml version='1.0'?>
<!DOCTYPE JANFEAInput SYSTEM "NairnMPM.dtd">
<JANFEAInput version='3'>
  <Header><Description>vibrating bar $var</Description><Analysis>11</Analysis>
    <ConsistentUnits length="mm" mass="g" time="ms"/></Header>
  <MPMHeader>
    <MPMMethod>$MPMMETHOD</MPMMethod>$skip
    <GIMP type="$SHAPE"/>
    <MatlPtsPerElement>4</MatlPtsPerElement>
    <Timing CFL="$CFL"/>
    <MaxTime>$tmax</MaxTime>
    <ArchiveTime>$tmax</ArchiveTime>
    <ArchiveRoot>Results_bar/bar.</ArchiveRoot>
    <MPMArchiveOrder>iYYYNNNNNNNNNNNNNN</MPMArchiveOrder>
    <GlobalArchiveTime>0.02</GlobalArchiveTime>
    <GlobalArchive type="Kinetic Energy"/>
    <GlobalArchive type="Strain Energy"/>
    <GlobalArchive type="velx" matname="bar"/>
  </MPMHeader>
  <Mesh output="file">
    <Grid xmin="-$(m "4*$CELL")" xmax="$(m "$L+4*$CELL")" ymin="-$(m "4*$CELL")" ymax="$(m "$H+4*$CELL")">
      <Horiz cellsize="$CELL"/><Vert cellsize="$CELL"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="bar" thick="1"><vel0X>sin(pi*x/(2*$L))</vel0X><Rect xmin="0" xmax="$L" ymin="0" ymax="$H"/></Body>
  </MaterialPoints>
  <Material Type="1" Name="bar"><rho>0.001</rho><E>1000</E><nu>0</nu><alpha>0</alpha></Material>
  <GridBCs>
    <BCLine x1="0" x2="0" y1="-$(m "4*$CELL")" y2="$(m "$H+4*$CELL")" tolerance="$(m "$CELL/4")"><DisBC dir="1" style="1" vel="0"/></BCLine>
  </GridBCs>
$(nairn_custom_tasks "$var")
</JANFEAInput>
X
nairn_run "$np"
PYTHONPATH="$here" python3 - "$var" "$np" "$nairn_wall" <<'PY'
import math, sys
import nairn_results
var, np_, wall = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
steps, npts, rows, col = nairn_results.load()
w = math.pi * 1000 / 800
err = max(abs(r[col['velx mat 1']] - 2 / math.pi * math.cos(w * r[0])) for r in rows)
e = lambda r: r[col['Kinetic Energy']] + r[col['Strain Energy']]
print(f'NairnMPM bar {var} threads={np_} points={npts} steps={steps} wall_s={wall:.2f} '
      f'particle_steps_per_s={npts*steps/wall:.3g} max_velocity_error={err:.3g} energy_ratio={e(rows[-1])/e(rows[0]):.5f}')
PY
