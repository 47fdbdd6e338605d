// A bar 0.2 x 0.02 x 0.02 m of hexahedra, 10 x 2 x 2 (generate.py).
L = 0.2; B = 0.02; H = 0.02;
Point(1) = {0, 0, 0};
Point(2) = {0, B, 0};
Line(1) = {1, 2};
Transfinite Line{1} = 3;
e1[] = Extrude{0, 0, H}{ Line{1}; Layers{2}; Recombine; };
e2[] = Extrude{L, 0, 0}{ Surface{e1[1]}; Layers{10}; Recombine; };
Physical Volume("bar") = {e2[1]};
Physical Surface("root") = {e1[1]};
Physical Surface("tip") = {e2[0]};
