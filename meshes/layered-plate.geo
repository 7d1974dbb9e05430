// gmsh -2
// A plate [0,1]x[0,0.2] of two layers, "inner" y <= 0.1 and "outer" above, for materials per
// region (options/examples/layered-plate.yaml): 10x2 quadrilaterals per layer, conforming
// on y = 0.1. Face sets: "bottom" y = 0, "top" y = 0.2, "left" x = 0, "right" x = 1 (each
// side of both layers).
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 0.1, 0};
Point(4) = {0, 0.1, 0};
Point(5) = {1, 0.2, 0};
Point(6) = {0, 0.2, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Line(5) = {3, 5};
Line(6) = {5, 6};
Line(7) = {6, 4};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7};
Plane Surface(2) = {2};
Transfinite Curve {1, 3, 6} = 11;
Transfinite Curve {2, 4, 5, 7} = 3;
Transfinite Surface {1, 2};
Recombine Surface {1, 2};
Physical Curve("bottom", 1) = {1};
Physical Curve("right", 2) = {2, 5};
Physical Curve("top", 3) = {6};
Physical Curve("left", 4) = {4, 7};
Physical Surface("inner", 1) = {1};
Physical Surface("outer", 2) = {2};
