// Paper 7.9 (undulation of a particle between two blocks): the meshed bottom block B2.
// x in [-0.5, 1.5] covers the particle's 1 m of horizontal travel from A (x = 0) to B (x = 1) plus its
// radius r = 0.5 m on either side; height H = 0.5 m, top surface at y = 0 (the particle's centre starts
// at y = 0.5 + 0.25, midway in the 0.5 m of free centre travel, math note 7.9).
DefineConstant[ lc = 0.1 ];
Point(1) = {-0.5, -0.5, 0, lc};
Point(2) = {1.5, -0.5, 0, lc};
Point(3) = {1.5, 0, 0, lc};
Point(4) = {-0.5, 0, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("block") = {1};
Physical Curve("base") = {1};
Physical Curve("top") = {3};
