// The 3D block of prm/block-3d.prm as a Gmsh geometry: the unit square of
// square.geo extruded by 1 in z. Physical surface tags are the generated
// block's boundary ids (1 left, 2 bottom, 3/5 top left/right half, 4/6 right
// upper/lower half, 7 the faces z = 0 and z = 1). For the nested start on a
// mesh without coarser levels (tests/unit/nested_start_any_mesh.cc, which
// sets lc) and bench/cold_start/any_mesh_bench.py:
//   gmsh -3 -clmax 0.03 block-3d.geo -o block-3d.msh
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
out[] = Extrude {0, 0, 1} {Surface{1};};
// out[0] the face z = 1, out[1] the volume, out[2..7] the sides on lines 1..6
Physical Surface(2) = {out[2]};
Physical Surface(6) = {out[3]};
Physical Surface(4) = {out[4]};
Physical Surface(5) = {out[5]};
Physical Surface(3) = {out[6]};
Physical Surface(1) = {out[7]};
Physical Surface(7) = {1, out[0]};
Physical Volume(1) = {out[1]};
