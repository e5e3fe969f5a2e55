#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of fmpm's parameters/rigid_rotation.prm (units mm-g-ms):
# disk R = 300 mm at (500,500), omega = 2 rad/s, K = 400 Pa, G = 200 Pa, rho = 1 kg/m^3,
# 24 x 24 cells on 1000 mm, 2x2 points per cell, plane strain, to 1 s.
# Used for doc/studies/stability.md, "High orders and the shape function".
# Needs NairnMPM (see nairn_common.sh).
# Prints the steps, E_end/E_0 and the largest E/E_0 (NairnMPM does not stop when the energy grows).
# usage: nairn_rotation.sh VARIANT CFL   VARIANT = FLIP | XPIC<k> | FMPM<k>
# env: SHAPE (Dirac = classic, uGIMP, lCPDI), MPMMETHOD (2 USAVG, 3 USL), SKIPPOST (1: USAVG-/USL-)
set -euo pipefail
var=${1:?variant}; CFL=${2:?CFL}; SHAPE=${SHAPE:-Dirac}; MPMMETHOD=${MPMMETHOD:-2}
here=$(cd "$(dirname "$0")" && pwd); source "$here/nairn_common.sh"
nairn_binary; nairn_task "$var" > /dev/null
skip=""; [[ ${SKIPPOST:-0} == 1 ]] && skip="<SkipPostExtrapolation/>"
nairn_workdir nrot
cat > in.xml <<X
<?xml version='1.0'?>
<!DOCTYPE JANFEAInput SYSTEM "NairnMPM.dtd">
<JANFEAInput version='3'>
  <Header><Description>rotation $var</Description><Analysis>10</Analysis>
    <ConsistentUnits length="mm" mass="g" time="ms"/></Header>
  <MPMHeader>
    <MPMMethod>$MPMMETHOD</MPMMethod>$skip
    <GIMP type="$SHAPE"/>
    <MatlPtsPerElement>4</MatlPtsPerElement>
    <Timing CFL="$CFL"/>
    <MaxTime>1000</MaxTime>
    <ArchiveTime>1000</ArchiveTime>
    <ArchiveRoot>Results/rot.</ArchiveRoot>
    <MPMArchiveOrder>iYYYNNNNNNNNNNNNNN</MPMArchiveOrder>
    <GlobalArchiveTime>50</GlobalArchiveTime>
    <GlobalArchive type="Kinetic Energy"/>
    <GlobalArchive type="Strain Energy"/>
  </MPMHeader>
  <Mesh output="file">
    <Grid xmin="0" xmax="1000" ymin="0" ymax="1000" thickness="1">
      <Horiz nx="24"/><Vert ny="24"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="disk" thick="1"><vel0X>-0.002*(y-500)</vel0X><vel0Y>0.002*(x-500)</vel0Y><Oval xmin="200" xmax="800" ymin="200" ymax="800"/></Body>
  </MaterialPoints>
  <Material Type="1" Name="disk"><rho>1e-6</rho><E>5.142857142857e-4</E><nu>0.285714285714</nu><alpha>0</alpha></Material>
$(nairn_custom_tasks "$var")
</JANFEAInput>
X
mkdir -p Results
nairn_run 1 keep-going
echo "$var CFL=$CFL wall=$nairn_wall dir=$PWD"
grep -i -E "error|exception|terminated|unstable|left the grid" output.txt | head -3 || true
grep -E "Calculation Steps" output.txt
PYTHONPATH="$here" python3 - <<'PY'
import nairn_results
steps, points, rows, col = nairn_results.load()
e = lambda r: r[col['Kinetic Energy']] + r[col['Strain Energy']]
print(f"t_end={rows[-1][0]} E_end/E_0={e(rows[-1])/e(rows[0]):.4f} maxE/E0={max(e(r) for r in rows)/e(rows[0]):.4f}")
PY
