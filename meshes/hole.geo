// Block with a hole: a 2 m x 2 m square with a circular hole of radius 0.4 m at its centre.
// Its boundary has two loops: the outer one counter-clockwise, the hole clockwise (math note 9.2).
DefineConstant[ lc = 0.15 ];
Point(1) = {-1, -1, 0, lc};
Point(2) = {1, -1, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {-1, 1, 0, lc};
Point(5) = {0, 0, 0, lc};
Point(6) = {0.4, 0, 0, lc};
Point(7) = {0, 0.4, 0, lc};
Point(8) = {-0.4, 0, 0, lc};
Point(9) = {0, -0.4, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Circle(5) = {6, 5, 7};
Circle(6) = {7, 5, 8};
Circle(7) = {8, 5, 9};
Circle(8) = {9, 5, 6};
Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Physical Surface("block") = {1};
Physical Curve("base") = {1};
Physical Curve("hole") = {5, 6, 7, 8};
