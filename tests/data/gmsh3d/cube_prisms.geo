// cube_prisms.msh: gmsh -3 cube_prisms.geo -o cube_prisms.msh (Gmsh 4.8.4)
Point(1) = {0,0,0,0.4}; Point(2) = {1,0,0,0.4}; Point(3) = {1,1,0,0.4}; Point(4) = {0,1,0,0.4};
Line(1) = {1,2}; Line(2) = {2,3}; Line(3) = {3,4}; Line(4) = {4,1};
Curve Loop(1) = {1,2,3,4}; Plane Surface(1) = {1};
out[] = Extrude {0,0,1} { Surface{1}; Layers{2}; Recombine; };
Physical Volume(1) = {out[1]};
Physical Surface("top") = {out[0]};
Mesh.MshFileVersion = 4.1;
