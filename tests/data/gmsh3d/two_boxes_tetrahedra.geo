// two_boxes_tetrahedra.msh: gmsh -3 two_boxes_tetrahedra.geo -o two_boxes_tetrahedra.msh (Gmsh 4.8.4)
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 2, 0.5};
Box(2) = {1, 0, 0, 1, 2, 0.5};
Coherence;
Physical Volume("left", 5) = {1};
Physical Volume(7) = {2};
Physical Surface("bottom", 3) = {Surface{:}}; 
Mesh.MeshSizeMax = 0.8;
Mesh.MshFileVersion = 4.1;
