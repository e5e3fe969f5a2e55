#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of fmpm's parameters/spheres_contact_3d.prm (units mm-g-ms): two linear elastic
# spheres, R = 200 mm at (405, 250, 250) and (845, 250, 250), each moving toward the other at 1 m/s,
# E = 0.1 MPa, nu = 0.3, rho = 1 g/cm^3, 1250 x 500 x 500 mm grid of 30 x 12 x 12 cells, 2x2x2 points
# per cell, uGIMP, USAVG+, Courant 0.4, frictionless contact with logistic-regression normals,
# to 300 ms. One archive at the end (fmpm: 'Output/Interval = 0.3' to compare like with like).
# Needs a NairnMPM binary (see nairn_common.sh).
# Prints the points, steps, wall time, the kinetic energy at the end over the initial one and the
# energy error, (KE + SE)_end / (KE + SE)_0 - 1.
# usage: nairn_spheres_3d.sh [VARIANT] [THREADS]    VARIANT = FLIP (default) | FMPM<k> | XPIC<k>
set -euo pipefail
var=${1:-FLIP}; np=${2:-1}
here=$(cd "$(dirname "$0")" && pwd); source "$here/nairn_common.sh"
nairn_binary; nairn_task "$var" > /dev/null
nairn_workdir nspheres
material() {
  echo "  <Material Type=\"1\" Name=\"$1\"><rho>0.001</rho><E>0.1</E><nu>0.3</nu><alpha>0</alpha></Material>"
}
cat > in.xml <<X
<?xml version='1.0'?>
<!DOCTYPE JANFEAInput SYSTEM "NairnMPM.dtd">
<JANFEAInput version='3'>
  <Header><Description>spheres 3d $var</Description><Analysis>12</Analysis>
    <ConsistentUnits length="mm" mass="g" time="ms"/></Header>
  <MPMHeader>
    <MPMMethod>2</MPMMethod>
    <GIMP type="uGIMP"/>
    <MatlPtsPerElement>8</MatlPtsPerElement>
    <Timing CFL="0.4"/>
    <MaxTime>300</MaxTime>
    <ArchiveTime>300</ArchiveTime>
    <ArchiveRoot>Results_spheres/spheres.</ArchiveRoot>
    <MPMArchiveOrder>iYYYNNNNNNNNNNNNNN</MPMArchiveOrder>
    <GlobalArchiveTime>10</GlobalArchiveTime>
    <GlobalArchive type="Kinetic Energy"/>
    <GlobalArchive type="Strain Energy"/>
    <MultiMaterialMode Normals="6"><Friction>0</Friction></MultiMaterialMode>
  </MPMHeader>
  <Mesh output="file">
    <Grid xmin="0" xmax="1250" ymin="0" ymax="500" zmin="0" zmax="500">
      <Horiz nx="30"/><Vert ny="12"/><Depth nz="12"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="sphere0" vx="1" vy="0" vz="0"><Sphere xmin="205" xmax="605" ymin="50" ymax="450" zmin="50" zmax="450"/></Body>
    <Body matname="sphere1" vx="-1" vy="0" vz="0"><Sphere xmin="645" xmax="1045" ymin="50" ymax="450" zmin="50" zmax="450"/></Body>
  </MaterialPoints>
$(material sphere0)
$(material sphere1)
$(nairn_custom_tasks "$var")
</JANFEAInput>
X
nairn_run "$np"
PYTHONPATH="$here" python3 - "$var" "$np" "$nairn_wall" <<'PY'
import sys
import nairn_results
var, np_, wall = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
steps, npts, rows, col = nairn_results.load()
k = lambda r: r[col['Kinetic Energy']]
e = lambda r: k(r) + r[col['Strain Energy']]
print(f'NairnMPM spheres 3d {var} threads={np_} points={npts} steps={steps} wall_s={wall:.2f} '
      f'KE_end/KE_0={k(rows[-1]) / k(rows[0]):.4f} energy_error={e(rows[-1]) / e(rows[0]) - 1:.2e}')
PY
