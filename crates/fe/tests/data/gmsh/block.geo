// A steel block 0.1 x 0.04 x 0.02 m, unstructured tetrahedra (generate.py).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.04, 0.02};
Physical Volume("block") = {1};
Physical Surface("root") = {1};   // the face x = 0
Physical Surface("tip") = {2};    // the face x = 0.1
Physical Point("corner") = {2};   // (0, 0, 0)
Mesh.CharacteristicLengthMax = 0.03;
