// die2d meshed by Gmsh with quadrilaterals of edge about h/2 everywhere (Mesh/Source = gmsh): the kind of
// mesh the incremental run's new meshes are, for its steady comparison (benchmarks/extrusion_start.py --gmsh).
// gmsh -2 -format msh22 -setnumber h 0.6 die2d-uniform.geo -o die2d-uniform.msh
// Boundary ids as in die2d.md: 1 inlet, 3 container, 4 die face + land, 2 outlet, 5 axis.
DefineConstant[ h = {0.6, Name "h"} ];
xd = 14.25/Tan(70*Pi/180);
Point(1) = {-20, 0, 0, h}; Point(2) = {-20, 19, 0, h}; Point(3) = {0, 19, 0, h};
Point(4) = {xd, 4.75, 0, h}; Point(5) = {xd+15, 4.75, 0, h}; Point(6) = {xd+15, 0, 0, h};
Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,5}; Line(5) = {5,6}; Line(6) = {6,1};
Curve Loop(1) = {1,2,3,4,5,6}; Plane Surface(1) = {1};
Physical Curve(1) = {1}; Physical Curve(3) = {2}; Physical Curve(4) = {3, 4};
Physical Curve(2) = {5}; Physical Curve(5) = {6}; Physical Surface(100) = {1};
Mesh.MeshSizeExtendFromBoundary = 1; Mesh.MeshSizeFromPoints = 1; Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6; Mesh.RecombineAll = 1; Mesh.SubdivisionAlgorithm = 1;
