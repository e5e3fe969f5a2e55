#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of its RadialPressureDisk.fmcmd (NairnMPM/input/Scripted_Input) written as XML, linear
# elastic (units mm-g-ms): axisymmetric solid disk, radius b = 50 mm, depth 10 mm, E = 2300 MPa,
# nu = 0.33, rho = 1.2 g/cm^3; z = 0 and z = 10 mm symmetry planes (epsilon_zz = 0), grid v_r = 0 on the
# axis, a radial traction on r = b ramped linearly to PO (default -2.3 MPa, compression) over RAMP
# (default 0.5) of the run, then held; the run lasts MULT (default 100) transit times b/c, Courant 0.4,
# USAVG+, 2x2 points per cell.
# Exact (Lame, solid disk, no inner pressure): sigma_rr = sigma_thetatheta = PO, sigma_zz = 2 nu PO.
# Needs a NairnMPM binary (see nairn_common.sh).
# Prints points, steps, wall time, particle-steps/s, the global (particle mean) sigma_rr, sigma_zz,
# sigma_thetatheta at the end and their mean over the last tenth of the run, with relative errors
# and also against J sigma_exact, J = 1 + tr(eps) of the exact strains: NairnMPM's means follow it (a
# reference-configuration measure in its traction or stress; the small-strain closed form cannot tell which).
# usage: nairn_radial_disk.sh [THREADS]
# env: SHAPE (lCPDI | uGIMP | Dirac; default lCPDI), CELL (mm, default 2.5), PO, MULT, RAMP, CFL (default 0.4)
set -euo pipefail
np=${1:-1}
here=$(cd "$(dirname "$0")" && pwd); source "$here/nairn_common.sh"; source "$here/nairn_axisymmetric.sh"
nairn_binary
SHAPE=${SHAPE:-lCPDI}; CELL=${CELL:-2.5}; PO=${PO:--2.3}; MULT=${MULT:-100}; RAMP=${RAMP:-0.5}; CFL=${CFL:-0.4}
E=2300; nu=0.33; rho=0.0012; b=50; depth=10; border=2
tmax=$(m "$MULT*$b/sqrt($E/$rho)"); tramp=$(m "$RAMP*$tmax"); rate=$(m "$PO/$tramp")
nairn_workdir ndisk
{
nairn_axi_head 'disk under radial pressure' 'Results_disk/disk.'
cat <<X
  <Mesh output="file">
    <Grid xmin="-$(m "$border*$CELL")" xmax="$(m "$b+$border*$CELL")" ymin="-$(m "$border*$CELL")" ymax="$(m "$depth+$border*$CELL")">
      <Horiz cellsize="$CELL"/><Vert cellsize="$CELL" symmin="0" symmax="$depth"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="disk" thick="1"><Rect xmin="0" xmax="$b" ymin="0" ymax="$depth"/></Body>
  </MaterialPoints>
X
nairn_axi_material disk
cat <<X
  <GridBCs>
    <BCLine x1="-$(m "$CELL/2")" x2="-$(m "$CELL/2")" y1="-$(m "$border*$CELL")" y2="$(m "$depth+$border*$CELL")" tolerance="$(m "0.55*$CELL")"><DisBC dir="1" style="1" vel="0"/></BCLine>
  </GridBCs>
  <ParticleBCs>
    <BCLine x1="$b" x2="$b" y1="0" y2="$depth" tolerance="$(m "$CELL/2")">
      <TractionBC dir="1" face="2" style="2" stress="$rate"/>
      <TractionBC dir="1" face="2" style="2" stress="$(m "-($rate)")" time="$tramp"/>
    </BCLine>
  </ParticleBCs>
</JANFEAInput>
X
} > in.xml
nairn_run "$np"
nairn_axi_report 'radial disk' "$PO" "$(m "2*$nu*$PO")" "$PO"
