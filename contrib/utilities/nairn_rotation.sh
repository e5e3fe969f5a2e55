#!/bin/bash
# SPDX-License-Identifier: LGPL-2.1-or-later
# NairnMPM twin of fmpm's parameters/rigid_rotation.prm (units mm-g-ms):
# disk R = 300 mm at (500,500), omega = 2 rad/s, K = 400 Pa, G = 200 Pa, rho = 1 kg/m^3,
# 24 x 24 cells on 1000 mm, 2x2 points per cell, plane strain, to 1 s.
# Used for doc/studies/stability.md, "High orders and the shape function".
# Needs NairnMPM (github.com/nairnj/nairn-mpm-fea; binary in ~/.nairn/bin or $NAIRN_DIR/bin, as
# for contrib/utilities/nairn_bar.sh).
# Prints the steps, E_end/E_0 and the largest E/E_0 (NairnMPM does not stop when the energy grows).
# usage: nairn_rotation.sh VARIANT CFL   VARIANT = FLIP | XPIC<k> | FMPM<k>
# env: SHAPE (Dirac = classic, uGIMP, lCPDI), MPMMETHOD (2 USAVG, 3 USL), SKIPPOST (1: USAVG-/USL-)
set -euo pipefail
var=$1; CFL=$2; SHAPE=${SHAPE:-Dirac}; MPMMETHOD=${MPMMETHOD:-2}
skip=""; [[ ${SKIPPOST:-0} == 1 ]] && skip="<SkipPostExtrapolation/>"
case $var in
  FLIP) task="" ;;
  XPIC*) task="<Schedule name=\"PeriodicXPIC\"><Parameter name=\"XPICOrder\">${var#XPIC}</Parameter><Parameter name=\"periodicSteps\">1</Parameter></Schedule>" ;;
  FMPM*) task="<Schedule name=\"PeriodicXPIC\"><Parameter name=\"FMPMOrder\">${var#FMPM}</Parameter><Parameter name=\"periodicSteps\">1</Parameter></Schedule>" ;;
  *) echo "unknown variant $var"; exit 2 ;;
esac
d=$(mktemp -d -t nrot.XXXXXX); cd "$d"
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
$( [[ -n $task ]] && echo "  <CustomTasks>$task</CustomTasks>" )
</JANFEAInput>
X
cp ${NAIRN_DIR:-$HOME/.nairn}/bin/NairnMPM.dtd . 2>/dev/null || true
mkdir -p Results
start=$(date +%s.%N)
${NAIRN_DIR:-$HOME/.nairn}/bin/NairnMPM -np 1 in.xml > out.mpm 2>&1 || true
end=$(date +%s.%N)
g=$(ls Results/*global* 2>/dev/null | head -1 || true)
echo "$var CFL=$CFL wall=$(awk "BEGIN{print $end-$start}") dir=$d"
grep -i -E "error|exception|terminated|unstable|left the grid" out.mpm | head -3 || true
grep -E "Calculation Steps" out.mpm
python3 - <<'PY'
import glob,re
g=glob.glob('Results/*.global')[0]
lines=open(g).readlines()
rows=[list(map(float,l.split())) for l in lines if l.strip() and not l.startswith('#')]
e=lambda r:r[1]+r[2]
print(f"t_end={rows[-1][0]} E_end/E_0={e(rows[-1])/e(rows[0]):.4f} maxE/E0={max(e(r) for r in rows)/e(rows[0]):.4f}")
PY
