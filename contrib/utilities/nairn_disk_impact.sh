#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of fmpm's parameters/disk_impact.prm (units mm-g-ms): two neo-Hookean disks,
# R = 10 mm at (11.5, 12) and (32.5, 12), each moving toward the other at 8.165 m/s, E = 1000 MPa,
# nu = 0.33 (K = 980.39 MPa, G = 375.94 MPa, U(J) = (K/2)((J^2-1)/2 - ln J)), rho = 1.5 g/cm^3,
# plane strain, 44 x 24 mm grid of 0.5 mm cells, 2x2 points per cell, lCPDI, USL-, Courant 0.2,
# frictionless contact with logistic-regression normals, to 0.245 ms.
# Needs a NairnMPM binary (see nairn_common.sh).
# Prints the points, steps, wall time and the energy lost, 1 - (KE + SE)_end / (KE + SE)_0.
# usage: nairn_disk_impact.sh VARIANT [THREADS]    VARIANT = FLIP | FMPM<k> | XPIC<k>
# env: CELL (mm, default 0.5), SHAPE (NairnMPM's shape function, default lCPDI; B2SPLINE, B2GIMP,
#      B2CPDI for B-splines), DX and DY (mm, default 0: both disks moved by (DX, DY), fmpm's
#      Body n/Center; the points stay on the cell lattice, so the set of points changes)
set -euo pipefail
var=${1:?variant}; np=${2:-1}
here=$(cd "$(dirname "$0")" && pwd); source "$here/nairn_common.sh"
nairn_binary; nairn_task "$var" > /dev/null
CELL=${CELL:-0.5}
SHAPE=${SHAPE:-lCPDI}
DX=${DX:-0}; DY=${DY:-0}
oval() { # xmin xmax: the disk's box moved by (DX, DY)
  python3 -c "import sys; dx, dy = float(sys.argv[3]), float(sys.argv[4]); print(f'<Oval xmin=\"{float(sys.argv[1]) + dx!r}\" xmax=\"{float(sys.argv[2]) + dx!r}\" ymin=\"{2 + dy!r}\" ymax=\"{22 + dy!r}\"/>')" "$1" "$2" "$DX" "$DY"
}
nairn_workdir ndisk
material() {
  echo "  <Material Type=\"28\" Name=\"$1\"><rho>0.0015</rho><K>980.392156862745</K><G>375.939849624060</G><UJOption>2</UJOption></Material>"
}
cat > in.xml <<X
<?xml version='1.0'?>
<!DOCTYPE JANFEAInput SYSTEM "NairnMPM.dtd">
<JANFEAInput version='3'>
  <Header><Description>disk impact $var</Description><Analysis>10</Analysis>
    <ConsistentUnits length="mm" mass="g" time="ms"/></Header>
  <MPMHeader>
    <MPMMethod>3</MPMMethod><SkipPostExtrapolation/>
    <GIMP type="$SHAPE"/>
    <MatlPtsPerElement>4</MatlPtsPerElement>
    <Timing CFL="0.2"/>
    <MaxTime>0.245</MaxTime>
    <ArchiveTime>0.245</ArchiveTime>
    <ArchiveRoot>Results_disks/disks.</ArchiveRoot>
    <MPMArchiveOrder>iYYYNNNNNNNNNNNNNN</MPMArchiveOrder>
    <GlobalArchiveTime>0.01</GlobalArchiveTime>
    <GlobalArchive type="Kinetic Energy"/>
    <GlobalArchive type="Strain Energy"/>
    <MultiMaterialMode Normals="6"><Friction>0</Friction></MultiMaterialMode>
  </MPMHeader>
  <Mesh output="file">
    <Grid xmin="0" xmax="44" ymin="0" ymax="24">
      <Horiz cellsize="$CELL"/><Vert cellsize="$CELL"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="disk0" thick="1" vx="8.16496580927726" vy="0">$(oval 1.5 21.5)</Body>
    <Body matname="disk1" thick="1" vx="-8.16496580927726" vy="0">$(oval 22.5 42.5)</Body>
  </MaterialPoints>
$(material disk0)
$(material disk1)
$(nairn_custom_tasks "$var")
</JANFEAInput>
X
nairn_run "$np"
PYTHONPATH="$here" python3 - "$var" "$np" "$nairn_wall" <<'PY'
import sys
import nairn_results
var, np_, wall = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
steps, npts, rows, col = nairn_results.load()
e = lambda r: r[col['Kinetic Energy']] + r[col['Strain Energy']]
import os
print(f'NairnMPM disk impact {var} shape={os.environ.get("SHAPE", "lCPDI")} threads={np_} points={npts} steps={steps} wall_s={wall:.2f} '
      f'energy_lost={100 * (1 - e(rows[-1]) / e(rows[0])):.2f}%')
PY
