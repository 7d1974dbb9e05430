// gmsh -3
// Wall of the bifurcating vessel (bifurcation.geoinc): tetrahedra; face sets inlet_end,
// left_end, right_end (its three annular ends), outer, interface.
Include "bifurcation.geoinc";
Physical Surface("inlet_end", 1) = {inlet_end()};
Physical Surface("left_end", 2) = {left_end()};
Physical Surface("right_end", 3) = {right_end()};
Physical Surface("outer", 5) = {outer_surface()};
Physical Surface("interface", 4) = {interface()};
Physical Volume("wall", 2) = {wall()};
