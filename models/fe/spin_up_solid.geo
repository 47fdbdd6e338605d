// The spin-up beam of docs/scenes.md §5 as a solid bar for models/spin_up_beam_solid.ron:
// L = 10 m along x, square section a = sqrt(12 I / A) = sqrt(6e-3) = 0.0774597 m (so that
// I / A = a^2 / 12 = 5e-4 m^2, the data's EI / EA), 20 x 1 x 1 twenty-node hexahedra
// (serendipity, second order incomplete), centred on the x axis.
// gmsh -3 -order 2 -setnumber Mesh.SecondOrderIncomplete 1 spin_up_solid.geo -format msh41 -o spin_up_solid.msh
L = 10; a = Sqrt(6e-3); e = 1e-6;
Point(1) = {0, -a/2, -a/2};
l[] = Extrude{L, 0, 0}{ Point{1}; Layers{20}; };
s[] = Extrude{0, a, 0}{ Line{l[1]}; Layers{1}; Recombine; };
v[] = Extrude{0, 0, a}{ Surface{s[1]}; Layers{1}; Recombine; };
Physical Volume("bar") = Volume{:};
Physical Surface("root") = Surface In BoundingBox{-e, -1, -1, e, 1, 1};
Physical Surface("tip") = Surface In BoundingBox{L - e, -1, -1, L + e, 1, 1};
