#!/bin/bash
# usage: make_xml.sh VARIANT(FLIP|FMPM<k>) > in.xml
var=$1
case $var in
  FLIP) task="" ;;
  FMPM*) task="<CustomTasks><Schedule name=\"PeriodicXPIC\"><Parameter name=\"FMPMOrder\">${var#FMPM}</Parameter><Parameter name=\"periodicSteps\">1</Parameter></Schedule></CustomTasks>" ;;
esac
cat <<X
<?xml version='1.0'?>
<!DOCTYPE JANFEAInput SYSTEM "NairnMPM.dtd"
[
 <!ENTITY modulus "1.0">
 <!ENTITY nu "0.33">
 <!ENTITY rho "1.5">
 <!ENTITY vel "2500">
 <!ENTITY maxtime "16">
 <!ENTITY atime "0.25">
 <!ENTITY cs "0.5">
 <!ENTITY hmax "52">
 <!ENTITY vmax "24">
]>
<JANFEAInput version='3'>
  <Header>
    <Description>TwoDisks.fmcmd (XML_Input) on 0.5 mm cells, uGIMP, USAVG+, frictionless LR multimaterial contact, $var</Description>
    <Analysis>10</Analysis>
  </Header>
  <MPMHeader>
    <MPMMethod>2</MPMMethod>
    <GIMP type="uGIMP"/>
    <MatlPtsPerElement>4</MatlPtsPerElement>
    <MaxTime units="ms">&maxtime;</MaxTime>
    <ArchiveTime units="ms">&maxtime;</ArchiveTime>
    <ArchiveRoot>Results/TwoDisks.</ArchiveRoot>
    <MPMArchiveOrder>iYYYYNNNNNNNNNNNNY</MPMArchiveOrder>
    <GlobalArchiveTime units="ms">&atime;</GlobalArchiveTime>
    <GlobalArchive type="velx" matname="Disk 1"/>
    <GlobalArchive type="Kinetic Energy"/>
    <GlobalArchive type="Strain Energy"/>
    <MultiMaterialMode Normals="6"/>
  </MPMHeader>
  <Mesh output="file">
    <Grid xmin="-&hmax;" xmax="&hmax;" ymin="-&vmax;" ymax="&vmax;">
      <Horiz cellsize="&cs;"/>
      <Vert cellsize="&cs;"/>
    </Grid>
  </Mesh>
  <MaterialPoints>
    <Body matname="Disk 1" angle="0" thick="1" vx="&vel;" vy="0">
      <Oval xmin="-45" xmax="-15" ymin="-15" ymax="15"/>
    </Body>
    <Body matname="Disk 2" angle="0" thick="1" vx="-&vel;" vy="0">
      <Oval xmin="15" xmax="45" ymin="-15" ymax="15"/>
    </Body>
  </MaterialPoints>
  <Material Type="1" Name="Disk 1">
    <rho>&rho;</rho><E>&modulus;</E><nu>&nu;</nu><alpha>60</alpha>
  </Material>
  <Material Type="1" Name="Disk 2">
    <rho>&rho;</rho><E>&modulus;</E><nu>&nu;</nu><alpha>60</alpha>
  </Material>
$task
</JANFEAInput>
X
