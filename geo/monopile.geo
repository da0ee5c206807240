// Monopile: a rigid-ish pile of diameter D embedded L in a soil cylinder,
// head at the soil surface. Meridional half plane: gmsh x = r, gmsh y = z.
//
//   z =  0  +------+---------------------------+   pile_head (loaded) | soil_top
//           | pile | pile_side (r = D/2)       |
//   z = -L  +------+ pile_base (z = -L)        |   soil_outer (r = R)
//           |            soil                  |
//   z = -depth +-------------------------------+   soil_bottom
//         r = 0                               r = R
//
// Parameters (axijoint --set NAME=VALUE): D, L, R (soil radius), depth
// (soil depth), size (element size along the pile), coarsen (far size /
// size), order (1|2), quads (0|1). The pile is a solid cylinder: give it
// the bending stiffness of the real section through its E (E_solid = E I
// / (pi D^4 / 64)).
If (!Exists(D)) D = 8; EndIf
If (!Exists(L)) L = 32; EndIf
If (!Exists(R)) R = 80; EndIf
If (!Exists(depth)) depth = 64; EndIf
If (!Exists(size)) size = 1; EndIf
If (!Exists(coarsen)) coarsen = 8; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf

a = D / 2;
far = coarsen * size;
Point(1) = {0, 0, 0, size};
Point(2) = {a, 0, 0, size};
Point(3) = {a, -L, 0, size};
Point(4) = {0, -L, 0, size};
Point(5) = {R, 0, 0, far};
Point(6) = {R, -depth, 0, far};
Point(7) = {0, -depth, 0, far};

Line(1) = {4, 3};   // pile_base
Line(2) = {3, 2};   // pile_side
Line(3) = {2, 1};   // pile_head
Line(4) = {1, 4};   // pile axis
Line(5) = {7, 6};   // soil_bottom
Line(6) = {6, 5};   // soil_outer
Line(7) = {5, 2};   // soil_top
Line(8) = {4, 7};   // soil axis

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, -2, -1, 8};
Plane Surface(2) = {2};

// Element size `size` along the pile, graded to `far` away from it.
Field[1] = Distance;
Field[1].CurvesList = {1, 2};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = size;
Field[2].SizeMax = far;
Field[2].DistMin = 2 * size;
Field[2].DistMax = L;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.ElementOrder = order;
Mesh.RecombineAll = quads;

Physical Surface("pile") = {1};
Physical Surface("soil") = {2};
Physical Curve("pile_base") = {1};
Physical Curve("pile_side") = {2};
Physical Curve("pile_head") = {3};
Physical Curve("axis") = {4, 8};
Physical Curve("soil_bottom") = {5};
Physical Curve("soil_outer") = {6};
Physical Curve("soil_top") = {7};
