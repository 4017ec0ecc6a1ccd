// Column under self-weight (math note 9.5): width 0.25 m, height H = 1 m, base on y = 0.
// Generated at lc = 0.05, 0.025, 0.0125 (column_1/2/3.msh): three successively refined unstructured meshes.
DefineConstant[ lc = 0.1 ];
Point(1) = {0.0, 0.0, 0, lc};
Point(2) = {0.25, 0.0, 0, lc};
Point(3) = {0.25, 1.0, 0, lc};
Point(4) = {0.0, 1.0, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("column") = {1};
Physical Curve("base") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
