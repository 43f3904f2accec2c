// The paper beam (2 m x 0.01 m) as 100 x 1 structured 8-node quadrilaterals (Gmsh type
// 16, "quad8"), the mesh of the built-in plane stress (stickslip's StripMesh 100 x 1):
//
//   gmsh -2 beam.geo -format msh41 -o beam.msh      (regenerate.sh)
//
// Physical groups name what the scene refers to: "clamp" the face x = 0, "tip" the free
// end's top corner (2, 0.01), "beam" the surface (its elements are the ones assembled).
L = 2.0;
h = 0.01;
Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, h, 0};
Point(4) = {0, h, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
// 101 nodes along, 2 through: 100 x 1 elements, uniform (Progression 1).
Transfinite Curve{1, 3} = 101;
Transfinite Curve{2, 4} = 2;
Transfinite Surface{1} = {1, 2, 3, 4};
Recombine Surface{1};
// Second order, serendipity (no centre node): quad8 rather than quad9.
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 1;
Physical Curve("clamp") = {4};
Physical Point("tip") = {3};
Physical Surface("beam") = {1};
