// A unit cube in 24-ish tetrahedra for the 3D reader's bad-input cases
// (tests/bad_input/cases.txt): gmsh -3 -format msh22 cube.geo -o cube.msh
// Physical surface tags (boundary ids): 1 the face x = 0 (clamped), 2 the
// face z = 0 (contact), 3 the face z = 1 (loaded).
Point(1) = {0, 0, 0, 0.5};
Point(2) = {1, 0, 0, 0.5};
Point(3) = {1, 1, 0, 0.5};
Point(4) = {0, 1, 0, 0.5};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 1} {Surface{1};};
Physical Surface(1) = {out[5]};
Physical Surface(2) = {1};
Physical Surface(3) = {out[0]};
Physical Volume(1) = {out[1]};
