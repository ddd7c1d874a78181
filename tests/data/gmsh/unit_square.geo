// Unit square: "clamped" = left + right, "load" = top, "contact" = bottom, "body" = surface.
// unit_square_triangles.msh and unit_square_quads.msh were made with Gmsh 4.8.4 (Debian):
//   gmsh -2 unit_square.geo -format msh41 -o unit_square_triangles.msh
// and, with the line "Recombine Surface{1};" appended to this file,
//   gmsh -2 unit_square.geo -format msh41 -o unit_square_quads.msh
// unit_square_parametric.msh: this file without its "Physical" lines (Gmsh then saves every
// element, points and lines included), with parametric node coordinates:
//   gmsh -2 unit_square.geo -format msh41 -setnumber Mesh.SaveParametric 1 -o unit_square_parametric.msh
lc = 0.5;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("contact", 11) = {1};
Physical Curve("clamped", 12) = {2, 4};
Physical Curve("load", 13) = {3};
Physical Surface("body", 21) = {1};
Mesh.MshFileVersion = 4.1;
