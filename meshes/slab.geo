// Small slab: 2 m x 0.3 m (e.g. held by bolts).
DefineConstant[ lc = 0.1 ];
Point(1) = {0, 0, 0, lc};
Point(2) = {2, 0, 0, lc};
Point(3) = {2, 0.3, 0, lc};
Point(4) = {0, 0.3, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("slab") = {1};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3};
