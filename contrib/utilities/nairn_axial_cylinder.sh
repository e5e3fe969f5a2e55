#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of its AxialLoadCylinder.fmcmd (NairnMPM/input/Scripted_Input) written as XML, linear
# elastic (units mm-g-ms): axisymmetric solid cylinder, radius Ro = 20 mm, length L = 20 mm, E = 2300 MPa,
# nu = 0.33, rho = 1.2 g/cm^3; z = 0 a symmetry plane, grid v_r = 0 on the axis and on the outer radius
# (confined), a uniform axial traction on z = L ramped linearly to SZZ (default -2.3 MPa, 0.1 %
# compression) over RAMP (default 0.5) of the run, then held; the run lasts MULT (default 40) transit
# times L/c, Courant 0.1, USAVG+, 2x2 points per cell.
# Exact (uniaxial strain): sigma_zz = SZZ, sigma_rr = sigma_thetatheta = nu/(1 - nu) SZZ.
# Needs a NairnMPM binary (see nairn_common.sh).
# Prints points, steps, wall time, particle-steps/s, the global (particle mean) sigma_rr, sigma_zz,
# sigma_thetatheta at the end and their mean over the last tenth of the run, with relative errors
# and also against J sigma_exact, J = 1 + tr(eps) of the exact strains: NairnMPM's means follow it (a
# reference-configuration measure in its traction or stress; the small-strain closed form cannot tell which).
# usage: nairn_axial_cylinder.sh [THREADS]
# env: SHAPE (lCPDI | uGIMP | Dirac; default lCPDI), CELL (mm, default 2), SZZ, MULT, RAMP, CFL (default 0.1)
set -euo pipefail
np=${1:-1}
here=$(cd "$(dirname "$0")" && pwd); source "$here/nairn_common.sh"; source "$here/nairn_axisymmetric.sh"
nairn_binary
SHAPE=${SHAPE:-lCPDI}; CELL=${CELL:-2}; SZZ=${SZZ:--2.3}; MULT=${MULT:-40}; RAMP=${RAMP:-0.5}; CFL=${CFL:-0.1}
E=2300; nu=0.33; rho=0.0012; L=20; Ro=20; border=3
tmax=$(m "$MULT*$L/sqrt($E/$rho)"); tramp=$(m "$RAMP*$tmax"); rate=$(m "$SZZ/$tramp")
nairn_workdir ncylinder
{
nairn_axi_head 'axially loaded cylinder' 'Results_cylinder/cyl.'
cat <<X
  <Mesh output="file">
    <Grid xmin="-$CELL" xmax="$(m "$Ro+$border*$CELL")" ymin="-$(m "$border*$CELL")" ymax="$(m "$L+$border*$CELL")">
      <Horiz cellsize="$CELL"/><Vert cellsize="$CELL" symmin="0"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="cylinder" thick="1"><Rect xmin="0" xmax="$Ro" ymin="0" ymax="$L"/></Body>
  </MaterialPoints>
X
nairn_axi_material cylinder
cat <<X
  <GridBCs>
    <BCLine x1="-$(m "$CELL/2")" x2="-$(m "$CELL/2")" y1="-$(m "$border*$CELL")" y2="$(m "$L+$border*$CELL")" tolerance="$(m "0.55*$CELL")"><DisBC dir="1" style="1" vel="0"/></BCLine>
    <BCLine x1="$(m "$Ro+$CELL/2")" x2="$(m "$Ro+$CELL/2")" y1="-$(m "$border*$CELL")" y2="$(m "$L+$border*$CELL")" tolerance="$(m "0.55*$CELL")"><DisBC dir="1" style="1" vel="0"/></BCLine>
  </GridBCs>
  <ParticleBCs>
    <BCLine x1="0" x2="$Ro" y1="$L" y2="$L" tolerance="$(m "$CELL/2")">
      <TractionBC dir="2" face="3" style="2" stress="$rate"/>
      <TractionBC dir="2" face="3" style="2" stress="$(m "-($rate)")" time="$tramp"/>
    </BCLine>
  </ParticleBCs>
</JANFEAInput>
X
} > in.xml
nairn_run "$np"
nairn_axi_report 'axial cylinder' "$(m "$nu/(1-$nu)*$SZZ")" "$SZZ" "$(m "$nu/(1-$nu)*$SZZ")"
