// gmsh -2
// Fluid of the Turek-Hron FSI benchmark: channel [0,2.5]x[0,0.41] minus the cylinder
// (centre (0.2,0.2), radius 0.05) and the flag (turek-hron.geoinc); unstructured quads
// only, graded from the body to the outlet.
// Face sets: 1 "bottom" wall y = 0, 2 "outflow" x = 2.5, 3 "top" wall y = 0.41, 4 "inflow" x = 0,
// 5 "cylinder" (the arcs facing the fluid), 6 "flag" (bottom, tip, top; same nodes as in
// turek-hron-flag.geo). Surface 1 "fluid".
Include "turek-hron.geoinc";
L = 2.5;  H = 0.41;

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, H, 0};
Point(4) = {0, H, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};

// The cylinder's wetted part: the big arc from (x0, 0.21) counter-clockwise to
// (x0, 0.19), in four arcs of less than 180 degrees.
Point(20) = {cx, cy, 0};
Point(21) = {cx, cy + rc, 0};
Point(22) = {cx - rc, cy, 0};
Point(23) = {cx, cy - rc, 0};
Circle(21) = {15, 20, 21};
Circle(22) = {21, 20, 22};
Circle(23) = {22, 20, 23};
Circle(24) = {23, 20, 11};

Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {21, 22, 23, 24, flagWet[]};
Plane Surface(1) = {1, 2};

// Sizes (turek-hron.geoinc): hb up to 0.01 from the cylinder and the flag, growing
// linearly to hf at 0.2 from them; hw in the near wake x in [0.5, 1], y in [0.13, 0.27],
// growing to hf over 0.15 around that box.
Field[1] = Distance;
Field[1].CurvesList = {21:24, flagWet[]};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hb;
Field[2].SizeMax = hf;
Field[2].DistMin = 0.01;
Field[2].DistMax = 0.2;
Field[3] = Box;
Field[3].VIn = hw;
Field[3].VOut = hf;
Field[3].XMin = 0.5;   Field[3].XMax = 1.0;
Field[3].YMin = 0.13;  Field[3].YMax = 0.27;
Field[3].Thickness = 0.15;
Field[4] = Min;
Field[4].FieldsList = {2, 3};
Background Field = 4;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;

// All quads: Frontal-Delaunay triangles paired by Blossom (which makes the segment count
// of every free curve even, so a perfect matching exists). "Frontal-Delaunay for quads"
// (Mesh.Algorithm = 8) crashes in gmsh 4.8.4; the full-quad recombinations (2, 3) need
// even transfinite counts (the tip halves have 1 segment at n = 1) and would split the
// flag's sides. scripts/check_turek_mesh.py checks the result.
Mesh.Algorithm = 6;               // Frontal-Delaunay
Mesh.RecombinationAlgorithm = 1;  // Blossom
Mesh.Smoothing = 3;
Recombine Surface{1};

Physical Curve("bottom", 1) = {1};
Physical Curve("outflow", 2) = {2};
Physical Curve("top", 3) = {3};
Physical Curve("inflow", 4) = {4};
Physical Curve("cylinder", 5) = {21:24};
Physical Curve("flag", 6) = {flagWet[]};
Physical Surface("fluid", 1) = {1};
