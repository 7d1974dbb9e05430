// gmsh -2
// The wall of options/examples/channel2d-named.yaml: [0,6]x[1,1.1] in 30x1 quadrilaterals
// on top of meshes/channel-fluid.geo, its sides named as the options file names them.
Point(1) = {0, 1, 0};
Point(2) = {6, 1, 0};
Point(3) = {6, 1.1, 0};
Point(4) = {0, 1.1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve {1, 3} = 31;
Transfinite Curve {2, 4} = 2;
Transfinite Surface {1};
Recombine Surface {1};
Physical Curve("interface", 1) = {1};
Physical Curve("downstream_end", 2) = {2};
Physical Curve("outer", 3) = {3};
Physical Curve("upstream_end", 4) = {4};
Physical Surface("vessel_wall", 1) = {1};
