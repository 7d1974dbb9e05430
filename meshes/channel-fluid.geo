// gmsh -2
// The channel of options/examples/channel2d-named.yaml: fluid [0,6]x[0,1] in 30x10
// quadrilaterals, its sides named as the options file names them.
Point(1) = {0, 0, 0};
Point(2) = {6, 0, 0};
Point(3) = {6, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve {1, 3} = 31;
Transfinite Curve {2, 4} = 11;
Transfinite Surface {1};
Recombine Surface {1};
Physical Curve("floor", 1) = {1};
Physical Curve("outlet", 2) = {2};
Physical Curve("interface", 3) = {3};
Physical Curve("inlet", 4) = {4};
Physical Surface("blood", 1) = {1};
