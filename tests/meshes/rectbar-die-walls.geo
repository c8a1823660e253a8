// The two die walls (die face and land) of the rectangular bar quarter
// (Mesh/Source = rectangular bar quarter, the Die2d defaults: 19 -> 4.75 in
// y at 70 degrees, 10 -> 6 in z over the same die length, land 15 mm),
// extended 5 mm beyond the bar, as Gmsh surface meshes of triangles for
// Contact/Die surfaces (tests/die_surface). Physical surface 4: the wall
// y = h(x); 7: the wall z = w(x).
//   gmsh -2 -format msh41 -setnumber wall 4 rectbar-die-walls.geo -o rectbar-die-y.msh
//   gmsh -2 -format msh41 -setnumber wall 7 rectbar-die-walls.geo -o rectbar-die-z.msh
If (!Exists(wall))
  wall = 4;
EndIf
h_i = 19; h_o = 4.75; w_i = 10; w_o = 6;
x_d = (h_i - h_o) / Tan(70 * Pi / 180);
x_e = x_d + 15;
lc = 2;
If (wall == 4)
  // y = h(x), over z in [0, w(x) + 5]
  Point(1) = {0, h_i, 0, lc};      Point(2) = {x_d, h_o, 0, lc};
  Point(3) = {x_d, h_o, w_o + 5, lc}; Point(4) = {0, h_i, w_i + 5, lc};
  Point(5) = {x_e, h_o, 0, lc};    Point(6) = {x_e, h_o, w_o + 5, lc};
Else
  // z = w(x), over y in [0, h(x) + 5]
  Point(1) = {0, 0, w_i, lc};      Point(2) = {x_d, 0, w_o, lc};
  Point(3) = {x_d, h_o + 5, w_o, lc}; Point(4) = {0, h_i + 5, w_i, lc};
  Point(5) = {x_e, 0, w_o, lc};    Point(6) = {x_e, h_o + 5, w_o, lc};
EndIf
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {2, 5}; Line(6) = {5, 6}; Line(7) = {6, 3};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2}; Plane Surface(2) = {2};
Physical Surface(wall) = {1, 2};
