// A rigid circular footing on the surface of a soil cylinder: the bearing
// capacity of a plastic soil (crates/solver/tests/plasticity.rs). Meridional
// half plane r >= 0: gmsh x = r, gmsh y = z (metres).
//
//   z = 0   +--footing--+------surface-----------+
//           |           ^ r = R (the footing edge, finest cells)
//      axis |            soil                    | outer (r = W)
//           |                                    |
//   z = -D  +---------------bottom---------------+
//         r = 0                               r = W
//
// The footing is a load's face (a `motion` moves it down as a rigid body:
// rough when held in r too, smooth when held in z only).
//
// Parameters (override with gmsh -setnumber NAME VALUE, or axijoint --set):
//   R        footing radius (default 1)
//   W, D     soil radius and depth in footing radii (defaults 5, 4)
//   size     cell size at the footing edge [m] (default 0.05)
//   coarsen  cell size far away / size (default 20)
//   order    1 = linear, 2 = quadratic elements
//   quads    1 = recombine into quadrilaterals, 0 = triangles
If (!Exists(R)) R = 1.0; EndIf
If (!Exists(W)) W = 5; EndIf
If (!Exists(D)) D = 4; EndIf
If (!Exists(size)) size = 0.05; EndIf
If (!Exists(coarsen)) coarsen = 20; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf

far = size * coarsen;
Point(1) = {0, 0, 0, 2 * size};
Point(2) = {R, 0, 0, size};
Point(3) = {W * R, 0, 0, far};
Point(4) = {W * R, -D * R, 0, far};
Point(5) = {0, -D * R, 0, far};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};

// Fine cells around the footing edge and under the footing (the plastic
// zone), growing away from it.
Field[1] = Distance;
Field[1].PointsList = {2};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = size;
Field[2].SizeMax = far;
Field[2].DistMin = 0.1 * R;
Field[2].DistMax = 2.5 * R;
Field[3] = Box;
Field[3].VIn = 3 * size;
Field[3].VOut = far;
Field[3].XMin = 0;
Field[3].XMax = 2.2 * R;
Field[3].YMin = -1.5 * R;
Field[3].YMax = 0;
Field[4] = Min;
Field[4].FieldsList = {2, 3};
Background Field = 4;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.ElementOrder = order;
Mesh.RecombineAll = quads;
Mesh.Algorithm = 6;

Physical Surface("soil") = {1};
Physical Curve("footing") = {1};
Physical Curve("surface") = {2};
Physical Curve("outer") = {3};
Physical Curve("bottom") = {4};
Physical Curve("axis") = {5};
