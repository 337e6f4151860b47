// Half of a ball of radius R, centre at the origin, touching the plane
// z = -R, for the frictional Hertz benchmark in 3D
// (prm/hertz-friction-3d.prm): the half y >= 0 of the lower half ball, so
// that a tangential load along x keeps the symmetry plane y = 0. Physical
// surface tags (boundary ids): 4 the symmetry plane y = 0, 3 the top face
// z = 0 (imposed displacement), 2 the spherical surface below z = -R/2
// (candidate contact zone), 5 the rest of it (free). Graded towards the
// contact point (0, 0, -R), h_contact there.
SetFactory("OpenCASCADE");
Geometry.OCCBoundsUseStl = 1;
R = 1;
h_contact = 0.01;
h_far = 0.15;
Sphere(1) = {0, 0, 0, R};
// OpenCASCADE's sphere is singular at its poles (0, 0, +-R): turn them away
// from the contact point
Rotate {{0, 1, 0}, {0, 0, 0}, Pi / 2} { Volume{1}; }
Box(2) = {-R, 0, -R, 2 * R, R, R};
BooleanIntersection(3) = {Volume{1}; Delete;}{Volume{2}; Delete;};
Rectangle(10) = {-R, 0, -R / 2, 2 * R, R};
parts() = BooleanFragments{Volume{3}; Delete;}{Surface{10}; Delete;};
e = 1e-6 * R;
y0() = Surface In BoundingBox{-R - e, -e, -R - e, R + e, e, e};
z0() = Surface In BoundingBox{-R - e, -e, -e, R + e, R + e, e};
below() = Surface In BoundingBox{-R - e, -e, -R - e, R + e, R + e, -R / 2 + e};
cut() = Surface In BoundingBox{-R - e, -e, -R / 2 - e, R + e, R + e, -R / 2 + e};
below() -= {y0(), cut()};
volumes() = Volume{:};
sphere() = Abs(CombinedBoundary{Volume{volumes()};});
sphere() -= {y0(), z0(), below()};
Physical Surface(2) = {below()};
Physical Surface(3) = {z0()};
Physical Surface(4) = {y0()};
Physical Surface(5) = {sphere()};
Physical Volume(1) = {volumes()};
contact_point() = Point In BoundingBox{-e, -e, -R - e, e, e, -R + e};
Field[1] = Distance;
Field[1].PointsList = {contact_point()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact;
Field[2].SizeMax = h_far;
Field[2].DistMin = 0.15;
Field[2].DistMax = 0.8;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
