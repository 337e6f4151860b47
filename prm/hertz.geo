// Quarter of a cylinder of radius R (center at the origin) for the Hertz
// benchmark (prm/hertz.prm), graded towards the contact point (0, -R).
// Generate the mesh with:  gmsh -2 -format msh22 hertz.geo -o hertz.msh
// Physical curve tags (boundary ids): 1 symmetry line x = 0, 2 the arc
// (candidate contact zone), 3 the top edge y = 0 (imposed displacement).
Include "hertz-geometry.geo";
h_contact = 0.0025;
h_far = 0.08;
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
