// Cantilever (math note 9.5): L = 10 m, h = 1 m (L/h = 10), clamped at x = 0 ("clamp"), tip at x = L.
// Generated at lc = 0.5, 0.25, 0.125 (cantilever_1/2/3.msh).
DefineConstant[ lc = 0.5 ];
Point(1) = {0.0, -0.5, 0, lc};
Point(2) = {10.0, -0.5, 0, lc};
Point(3) = {10.0, 0.5, 0, lc};
Point(4) = {0.0, 0.5, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("beam") = {1};
Physical Curve("clamp") = {4};
Physical Curve("tip") = {2};
