// gmsh -3
// Fluid of the 3D pressure-wave tube: cylinder r <= 0.5, z in [0, 5], hexahedra only
// (tetrahedra with -setnumber simplex 1).
// Face sets: 4 inlet z = 0, 2 outlet z = 5, 3 lateral r = 0.5 (the interface; the wall
// mesh tube3d-wall.geo has the same nodes there). Volume 1.
Include "tube3d-section.geoinc";

tops[] = {}; vols[] = {}; iface[] = {};
For k In {0:#fluidS[]-1}
  If (simplex)
    out[] = Extrude {0, 0, L} { Surface{fluidS[k]}; Layers{Nz}; };
  Else
    out[] = Extrude {0, 0, L} { Surface{fluidS[k]}; Layers{Nz}; Recombine; };
  EndIf
  tops[] += out[0];
  vols[] += out[1];
  If (fluidS[k] != 100)  // the central square has no arc
    iface[] += out[2];
  EndIf
EndFor

Physical Surface("inlet", 4) = {fluidS[]};
Physical Surface("outlet", 2) = {tops[]};
Physical Surface("interface", 3) = {iface[]};
Physical Volume("blood", 1) = {vols[]};
