<?xml version="1.0" standalone="no"?>

<!DOCTYPE DDA SYSTEM "geometry.dtd">
<Berkeley:DDA xmlns:Berkeley="http://www.tsoft.com/~bdoolin/dda">

<!-- The jointed mass of mass.geo, with a grouted bolt -->
<Berkeley:Geometry>

   <Berkeley:Edgenodedist distance="0.01"/>

   <Jointlist>
      <Joint type="1"> 0 0 10 0 </Joint>
      <Joint type="1"> 10 0 10 6 </Joint>
      <Joint type="1"> 10 6 0 6 </Joint>
      <Joint type="1"> 0 6 0 0 </Joint>
      <Joint type="2"> 4 -0.5 4 6.5 </Joint>
      <Joint type="2"> -0.5 3 10.5 3 </Joint>
   </Jointlist>

   <Matlinelist>
      <Line type="2"> 5 1 9 2 </Line>
   </Matlinelist>

   <Fixedpointlist>
      <Point> 1 0.5 </Point>
      <Point> 9 0.5 </Point>
   </Fixedpointlist>

   <Loadpointlist>
      <Point> 7 5 </Point>
   </Loadpointlist>

   <Measuredpointlist>
      <Point> 8 5 </Point>
   </Measuredpointlist>

   <Holepointlist>
      <Point> 2 4.5 </Point>
   </Holepointlist>

   <Boltlist>
      <Bolt type="2"> 6 1 6 5 </Bolt>
   </Boltlist>

</Berkeley:Geometry>
</Berkeley:DDA>
