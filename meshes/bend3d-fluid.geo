// gmsh -3
// Fluid of the bent tube (bend3d.geoinc): the disc r <= 0.5 swept along the curved axis.
// Face sets: 4 "inlet" z = 0, 2 "outlet" x = Rb + Lo, 3 "interface" r = 0.5 (lateral).
// Volume 1.
part = 0;
Include "bend3d.geoinc";
iface[] = {};
For k In {1:nf-1}  // block 0 is the central square: its lateral surfaces are inside
  iface[] += {first[3*k], first[3*k+1], first[3*k+2]};
EndFor
Physical Surface("inlet", 4) = {fluidS[]};
Physical Surface("outlet", 2) = {ends[]};
Physical Surface("interface", 3) = {iface[]};
Physical Volume("blood", 1) = {vols[]};
