<?xml version="1.0" standalone="no"?>
<!DOCTYPE DDA SYSTEM "geometry.dtd">
<Berkeley:DDA xmlns:Berkeley="http://www.tsoft.com/~bdoolin/dda">

<!-- A 45-degree rock slope, 20 m wide and 10 m high, cut by a bedding joint dipping
     21.8 degrees out of the face (y = 0.4 x - 1) and a vertical joint at x = 14: four blocks.
     The two blocks above the bedding joint rest on it; a grouted bolt from the face crosses it. -->
<Berkeley:Geometry>

   <Berkeley:Edgenodedist distance="0.0025"/>

   <Jointlist>
      <Joint type="1"> 0 0 20 0 </Joint>
      <Joint type="1"> 20 0 20 10 </Joint>
      <Joint type="1"> 20 10 10 10 </Joint>
      <Joint type="1"> 10 10 0 0 </Joint>
      <Joint type="2"> 2 -0.2 20.5 7.2 </Joint>
      <Joint type="2"> 14 -0.5 14 10.5 </Joint>
   </Jointlist>

   <!-- fixes the two blocks below the bedding joint, not the slope block's toe -->
   <Fixedpointlist>
      <Line> 3 0 20 0 </Line>
   </Fixedpointlist>

   <Measuredpointlist>
      <Point> 5 3 </Point>
   </Measuredpointlist>

   <Boltlist>
      <Bolt type="2"> 7 6 11 2 </Bolt>
   </Boltlist>

</Berkeley:Geometry>
</Berkeley:DDA>
