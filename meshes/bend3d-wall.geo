// gmsh -3
// Wall of the bent tube (bend3d.geoinc): the annulus 0.5 <= r <= 0.6 swept along the
// curved axis. Face sets: 1 inner r = 0.5 (the interface), 3 outer r = 0.6, 4 the end at
// the inlet, 2 the end at the outlet. Volume 1.
part = 1;
Include "bend3d.geoinc";
Physical Surface(1) = {third[]};
Physical Surface(3) = {first[]};
Physical Surface(4) = {wallS[]};
Physical Surface(2) = {ends[]};
Physical Volume(1) = {vols[]};
