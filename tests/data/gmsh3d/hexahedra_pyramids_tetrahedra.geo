// hexahedra_pyramids_tetrahedra.msh: gmsh -3 hexahedra_pyramids_tetrahedra.geo -o hexahedra_pyramids_tetrahedra.msh (Gmsh 4.8.4)
// hexahedra below, tetrahedra above: Gmsh joins them with pyramids
Point(1) = {0,0,0}; Point(2) = {1,0,0}; Point(3) = {1,1,0}; Point(4) = {0,1,0};
Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,1};
Curve Loop(1) = {1,2,3,4}; Plane Surface(1) = {1};
Transfinite Curve{1,2,3,4} = 3; Transfinite Surface{1}; Recombine Surface{1};
a[] = Extrude {0,0,1} { Surface{1}; Layers{2}; Recombine; };
b[] = Extrude {0,0,1} { Surface{a[0]}; };
Physical Volume(1) = {a[1]};
Physical Volume(2) = {b[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {b[0]};
Mesh.MshFileVersion = 4.1;
Mesh.MeshSizeMax = 0.5;
