// An eighth of a ball of radius R (prm/hertz-sphere-geometry.geo) for the
// Hertz benchmark in 3D (prm/hertz-sphere.prm), graded towards the contact
// point (0, 0, -R): tetrahedra of edge h_contact within dist_min of it,
// growing to h_far at distance dist_max. signorini meshes it through the Gmsh
// API when Mesh/File name names it; the same mesh by hand:
//   gmsh -3 -format msh41 hertz-sphere.geo -o hertz-sphere.msh
Include "hertz-sphere-geometry.geo";
h_contact = 0.005;
h_far = 0.12;
dist_min = 0.12;
dist_max = 0.8;
Field[1] = Distance;
Field[1].PointsList = {contact_point()};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_contact;
Field[2].SizeMax = h_far;
Field[2].DistMin = dist_min;
Field[2].DistMax = dist_max;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
