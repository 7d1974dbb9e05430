// gmsh -2
// Elastic flag of the Turek-Hron FSI benchmark: x in [x0, 0.6], y in [0.19, 0.21] with
// x0 = 0.2 + sqrt(0.05^2 - 0.01^2) (turek-hron.geoinc); a structured quad grid,
// 2r cells across and 30r along, r = 2^(n-1). Face sets: 4 "root", the clamped left side x = x0,
// 6 "flag": bottom, tip, top (same nodes as in turek-hron-fluid.geo). Surface 1 "flag".
Include "turek-hron.geoinc";

Line(15) = {15, 11};       // left side, clamped to the cylinder
Transfinite Curve{15} = 2*Nt+1;
Curve Loop(1) = {flagWet[], 15};
Plane Surface(1) = {1};
Transfinite Surface{1} = {11, 12, 14, 15};
Recombine Surface{1};

Physical Curve("root", 4) = {15};
Physical Curve("flag", 6) = {flagWet[]};
Physical Surface("flag", 1) = {1};
