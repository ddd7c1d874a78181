// l-bracket-3d.msh: gmsh -3 l-bracket-3d.geo -o l-bracket-3d.msh
// An L-shaped bracket 0.4 thick (y): a wall plate x in [0, 0.25], z in [0, 1.2], and an arm
// x in [0.25, 1.5], z in [0.6, 0.9]; the arm is steel (volume 2), the wall plate aluminium
// (volume 1). Physical surfaces: "wall" (x = 0, clamped), "top" (the arm's top, z = 0.9),
// "seat" (the arm's underside, z = 0.6: it rests on a foundation).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.25, 0.4, 1.2};
Box(2) = {0.25, 0, 0.6, 1.25, 0.4, 0.3};
BooleanFragments{ Volume{1, 2}; Delete; }{}
Coherence;
eps = 1e-6;
wall() = Surface In BoundingBox{-eps, -eps, -eps, eps, 0.4 + eps, 1.2 + eps};
seat() = Surface In BoundingBox{0.25 - eps, -eps, 0.6 - eps, 1.5 + eps, 0.4 + eps, 0.6 + eps};
top() = Surface In BoundingBox{0.25 - eps, -eps, 0.9 - eps, 1.5 + eps, 0.4 + eps, 0.9 + eps};
Physical Volume("plate", 1) = {1};
Physical Volume("arm", 2) = {2};
Physical Surface("wall") = {wall()};
Physical Surface("seat") = {seat()};
Physical Surface("top") = {top()};
Mesh.MeshSizeMax = 0.1;
Mesh.MshFileVersion = 4.1;
