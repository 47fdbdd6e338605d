// The steel bar of bar_mesh.inp (0.2 x 0.02 x 0.02 m, 6 x 1 x 1 hexahedra) for
// models/solid_bar_pendulum.ron, with its end faces as physical groups.
// gmsh -3 bar_solid.geo -format msh41 -o bar_solid.msh   (Gmsh 4.8.4)
L = 0.2; B = 0.02; H = 0.02;
Point(1) = {0,0,0}; Point(2) = {L,0,0};
Line(1) = {1,2};
Transfinite Line{1} = 7;
e1[] = Extrude{0,B,0}{ Line{1}; Layers{1}; Recombine; };
e2[] = Extrude{0,0,H}{ Surface{e1[1]}; Layers{1}; Recombine; };
Physical Volume("bar") = {e2[1]};
Physical Surface("root") = Surface In BoundingBox{-1e-6, -1, -1, 1e-6, 1, 1};
Physical Surface("tip") = Surface In BoundingBox{L - 1e-6, -1, -1, L + 1e-6, 1, 1};
