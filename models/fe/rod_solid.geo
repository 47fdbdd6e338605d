// The connecting rod of models/solid_slider_crank.ron (rod_nodes.txt: a steel bar 40 mm (y) x
// 20 mm (z), pin axes along z at x = 0 and x = 1.0 m, running 25 mm past them; 21 x 2 x 1
// bricks of 50 x 20 x 20 mm) as a Gmsh mesh, for models/solid_slider_crank_gmsh.ron.
// gmsh -3 rod_solid.geo -format msh41 -o rod_solid.msh   (Gmsh 4.8.4)
Point(1) = {-0.025, -0.02, -0.01};
a[] = Extrude{1.05, 0, 0}{ Point{1}; Layers{21}; };
s[] = Extrude{0, 0.04, 0}{ Line{a[1]}; Layers{2}; Recombine; };
v[] = Extrude{0, 0, 0.02}{ Surface{s[1]}; Layers{1}; Recombine; };
Physical Volume("rod") = {v[1]};
