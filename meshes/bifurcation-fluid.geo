// gmsh -3
// Fluid of the bifurcating vessel (bifurcation.geoinc): tetrahedra; face sets inlet,
// outlet_left, outlet_right, interface.
Include "bifurcation.geoinc";
Physical Surface("inlet", 1) = {inlet()};
Physical Surface("outlet_left", 2) = {outlet_left()};
Physical Surface("outlet_right", 3) = {outlet_right()};
Physical Surface("interface", 4) = {interface()};
Physical Volume("blood", 1) = {fluid()};
