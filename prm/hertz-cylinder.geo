// A half cylinder of radius R, center at the origin, touching the plane
// y = -R, for the frictional Hertz benchmark (prm/hertz-friction.prm): the
// whole contact zone is meshed, since a tangential load breaks the symmetry
// of prm/hertz.geo. Physical curve tags (boundary ids): 2 the arc
// (candidate contact zone), 3 the top edge y = 0 (imposed displacement).
// Graded towards the contact point (0, -R), h_contact there.
R = 1;
h_contact = 0.002;
h_far = 0.08;
Point(1) = {0, 0, 0};
Point(2) = {R, 0, 0};
Point(3) = {0, -R, 0};
Point(4) = {-R, 0, 0};
Circle(1) = {4, 1, 3};
Circle(2) = {3, 1, 2};
Line(3) = {2, 4};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Physical Curve(2) = {1, 2};
Physical Curve(3) = {3};
Physical Surface(1) = {1};
Field[1] = Distance;
Field[1].PointsList = {3};
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
