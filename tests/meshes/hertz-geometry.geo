// Geometry of the Hertz benchmark (prm/hertz.prm): a quarter of a cylinder
// of radius R, center at the origin, touching the plane y = -R. Physical
// curve tags (boundary ids): 1 symmetry line x = 0, 2 the arc (candidate
// contact zone), 3 the top edge y = 0 (imposed displacement). No mesh
// sizes: hertz.geo adds a graded size field; Mesh/Geometry file names this
// file for remeshing, which brings its own sizes.
R = 1;
Point(1) = {0, 0, 0};
Point(2) = {R, 0, 0};
Point(3) = {0, -R, 0};
Circle(1) = {3, 1, 2};
Line(2) = {2, 1};
Line(3) = {1, 3};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
Physical Curve(1) = {3};
Physical Curve(2) = {1};
Physical Curve(3) = {2};
Physical Surface(1) = {1};
