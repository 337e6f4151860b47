// The unit square of prm/block.prm as a Gmsh file, for the mesh tests of
// tests/bad_input/cases.txt: physical curve tags are the block's boundary ids
// (1 left, 2 bottom, 3/5 top left/right half, 4/6 right upper/lower half).
// Regenerate the three meshes (14 triangles) with
//   gmsh -2 -format msh22 square.geo -o square-22.msh
//   gmsh -2 -format msh41 square.geo -o square-41.msh
//   gmsh -2 -format msh41 -bin square.geo -o square-41-binary.msh
lc = 0.5;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 0.5, 0, lc};
Point(4) = {1, 1, 0, lc};
Point(5) = {0.5, 1, 0, lc};
Point(6) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 1};
Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};
Physical Curve(1) = {6};
Physical Curve(2) = {1};
Physical Curve(6) = {2};
Physical Curve(4) = {3};
Physical Curve(5) = {4};
Physical Curve(3) = {5};
Physical Surface(1) = {1};
