// gmsh -2
// Structure block [0,1]x[1,1.5] (the manufactured-solution wall), unstructured
// triangles for P2 runs. Physical curves: 1 bottom (interface), 2 right, 3 top, 4 left.
h = 0.25;
Point(1) = {0, 1, 0, h};
Point(2) = {1, 1, 0, h};
Point(3) = {1, 1.5, 0, h};
Point(4) = {0, 1.5, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve(1) = {1};
Physical Curve(2) = {2};
Physical Curve(3) = {3};
Physical Curve(4) = {4};
Physical Surface(1) = {1};
