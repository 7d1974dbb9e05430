// gmsh -3
// Wall of the 3D pressure-wave tube: annulus 0.5 <= r <= 0.6, z in [0, 5], hexahedra only
// (tetrahedra with -setnumber simplex 1).
// Face sets: 1 inner r = 0.5 (the interface; same nodes as tube3d-fluid.geo's set 3),
// 3 outer r = 0.6, 4 end z = 0, 2 end z = 5. Volume 1.
Include "tube3d-section.geoinc";

tops[] = {}; vols[] = {}; inner[] = {}; outer[] = {};
For k In {0:#wallS[]-1}
  If (simplex)
    out[] = Extrude {0, 0, L} { Surface{wallS[k]}; Layers{Nz}; };
  Else
    out[] = Extrude {0, 0, L} { Surface{wallS[k]}; Layers{Nz}; Recombine; };
  EndIf
  tops[] += out[0];
  vols[] += out[1];
  outer[] += out[2];
  inner[] += out[4];
EndFor

Physical Surface("interface", 1) = {inner[]};
Physical Surface("outer", 3) = {outer[]};
Physical Surface("inlet_end", 4) = {wallS[]};
Physical Surface("outlet_end", 2) = {tops[]};
Physical Volume("wall", 1) = {vols[]};
