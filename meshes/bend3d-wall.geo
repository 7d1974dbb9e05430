// gmsh -3
// Wall of the bent tube (bend3d.geoinc): the annulus 0.5 <= r <= 0.6 swept along the
// curved axis. Face sets: 1 inner r = 0.5 (the interface), 3 outer r = 0.6, 4 the end at
// the inlet, 2 the end at the outlet. Volume 1.
part = 1;
Include "bend3d.geoinc";
Physical Surface("interface", 1) = {third[]};
Physical Surface("outer", 3) = {first[]};
Physical Surface("inlet_end", 4) = {wallS[]};
Physical Surface("outlet_end", 2) = {ends[]};
Physical Volume("wall", 1) = {vols[]};
