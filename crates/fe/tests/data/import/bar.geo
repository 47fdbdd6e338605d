L = 0.2; B = 0.02; H = 0.02;
Point(1) = {0,0,0}; Point(2) = {L,0,0};
Line(1) = {1,2};
Transfinite Line{1} = 7;
e1[] = Extrude{0,B,0}{ Line{1}; Layers{1}; Recombine; };
e2[] = Extrude{0,0,H}{ Surface{e1[1]}; Layers{1}; Recombine; };
Physical Volume("bar") = {e2[1]};
