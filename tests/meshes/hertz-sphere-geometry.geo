// Geometry of the Hertz benchmark in 3D (prm/hertz-sphere.prm): an eighth of
// a ball of radius R, centre at the origin, touching the plane z = -R at its
// corner (0, 0, -R). Physical surface tags (boundary ids): 1 the symmetry
// plane x = 0, 4 the symmetry plane y = 0, 3 the top face z = 0 (imposed
// displacement), 2 the spherical surface below z = -R/2 (candidate contact
// zone), 5 the rest of the spherical surface (free). No mesh sizes:
// hertz-sphere.geo adds a graded size field.
SetFactory("OpenCASCADE");
// tight bounding boxes for the selections below
Geometry.OCCBoundsUseStl = 1;
R = 1;
Sphere(1) = {0, 0, 0, R};
// OpenCASCADE's sphere is singular at its poles (0, 0, +-R): turn them away
// from the contact point
Rotate {{0, 1, 0}, {0, 0, 0}, Pi / 2} { Volume{1}; }
Box(2) = {0, 0, -R, R, R, R};
BooleanIntersection(3) = {Volume{1}; Delete;}{Volume{2}; Delete;};
Rectangle(10) = {0, 0, -R / 2, R, R};
parts() = BooleanFragments{Volume{3}; Delete;}{Surface{10}; Delete;};
e = 1e-6 * R;
x0() = Surface In BoundingBox{-e, -e, -R - e, e, R + e, e};
y0() = Surface In BoundingBox{-e, -e, -R - e, R + e, e, e};
z0() = Surface In BoundingBox{-e, -e, -e, R + e, R + e, e};
below() = Surface In BoundingBox{-e, -e, -R - e, R + e, R + e, -R / 2 + e};
cut() = Surface In BoundingBox{-e, -e, -R / 2 - e, R + e, R + e, -R / 2 + e};
below() -= {x0(), y0(), cut()};
volumes() = Volume{:};
sphere() = Abs(CombinedBoundary{Volume{volumes()};});
sphere() -= {x0(), y0(), z0(), below()};
Physical Surface(1) = {x0()};
Physical Surface(2) = {below()};
Physical Surface(3) = {z0()};
Physical Surface(4) = {y0()};
Physical Surface(5) = {sphere()};
Physical Volume(1) = {volumes()};
contact_point() = Point In BoundingBox{-e, -e, -R - e, e, e, -R + e};
