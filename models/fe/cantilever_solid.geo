// A steel cantilever 0.2 x 0.01 x 0.01 m of 10 x 2 x 2 twenty-node hexahedra, built from two
// halves so that its mid-span section is a surface of the geometry and can be a physical
// group, for models/solid_cantilever.ron.
// gmsh -3 -order 2 -setnumber Mesh.SecondOrderIncomplete 1 cantilever_solid.geo -format msh41 -o cantilever_solid.msh
L = 0.2; h = 0.01; e = 1e-6;
Point(1) = {0, 0, 0};
a[] = Extrude{L/2, 0, 0}{ Point{1}; Layers{5}; };
b[] = Extrude{L/2, 0, 0}{ Point{a[0]}; Layers{5}; };
s[] = Extrude{0, h, 0}{ Line{a[1], b[1]}; Layers{2}; Recombine; };
v[] = Extrude{0, 0, h}{ Surface{s[1], s[5]}; Layers{2}; Recombine; };
Physical Volume("bar") = Volume{:};
Physical Surface("root") = Surface In BoundingBox{-e, -1, -1, e, 1, 1};
Physical Surface("mid") = Surface In BoundingBox{L/2 - e, -1, -1, L/2 + e, 1, 1};
Physical Surface("tip") = Surface In BoundingBox{L - e, -1, -1, L + e, 1, 1};
