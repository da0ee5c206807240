// A stiff cylindrical block of radius a on a larger base: the verification
// cases of docs/theory.md section 15 for nonlinear joints (torsional partial slip, uplift
// under eccentric compression). Meridional half plane: gmsh x = r, gmsh y = z.
//
//   z = hb      +------+                  block_top (loaded)
//               |      |
//         axis  |block | block_side
//               |      |
//   z = 0       +======+--------------+   contact (joint, r = 0 .. a), base_top
//               |                     |
//         axis  |        base         | base_side
//               |                     |
//   z = -hbase  +---------------------+   base_bottom (fixed)
//             r = 0   r = a         r = rb
//
// The mesh is refined along the contact (element size size / refine) and
// again towards its edge r = a (size / (2 refine)), where the traction
// concentrates.
//
// Parameters (gmsh -setnumber NAME VALUE):
//   a           block radius = contact radius [L]
//   size        element size far from the contact [L]
//   refine      size / (element size along the contact)
//   order       1 = linear, 2 = quadratic elements
//   quads       1 = recombine into quadrilaterals, 0 = triangles
If (!Exists(a)) a = 0.5; EndIf
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(refine)) refine = 4; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf

hb = a;          // block height
rb = 3 * a;      // base radius
hbase = 2 * a;   // base depth

Point(1) = {0, -hbase, 0, size};
Point(2) = {rb, -hbase, 0, size};
Point(3) = {rb, 0, 0, size};
Point(4) = {a, 0, 0, size};
Point(5) = {0, 0, 0, size};
Point(6) = {a, hb, 0, size};
Point(7) = {0, hb, 0, size};

Line(1) = {1, 2};   // base_bottom
Line(2) = {2, 3};   // base_side
Line(3) = {3, 4};   // base_top
Line(4) = {5, 4};   // contact, axis -> edge (xi = +r, eta = +z: block above)
Line(5) = {5, 1};   // axis, base
Line(6) = {4, 6};   // block_side
Line(7) = {6, 7};   // block_top
Line(8) = {7, 5};   // axis, block

Curve Loop(1) = {1, 2, 3, -4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {4, 6, 7, 8};
Plane Surface(2) = {2};

// Size field: size / refine along the contact, size / (2 refine) at r = a.
Field[1] = Distance;
Field[1].CurvesList = {4};
Field[1].NumPointsPerCurve = 100;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = size / refine;
Field[2].SizeMax = size;
Field[2].DistMin = 0.05 * a;
Field[2].DistMax = a;
Field[3] = Distance;
Field[3].PointsList = {4};
Field[4] = Threshold;
Field[4].InField = 3;
Field[4].SizeMin = size / (2 * refine);
Field[4].SizeMax = size;
Field[4].DistMin = 0.1 * a;
Field[4].DistMax = a;
Field[5] = Min;
Field[5].FieldsList = {2, 4};
Background Field = 5;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.ElementOrder = order;
Mesh.RecombineAll = quads;

Physical Surface("base") = {1};
Physical Surface("block") = {2};
Physical Curve("base_bottom") = {1};
Physical Curve("base_side") = {2};
Physical Curve("base_top") = {3};
Physical Curve("contact") = {4};
Physical Curve("block_side") = {6};
Physical Curve("block_top") = {7};
Physical Curve("axis") = {5, 8};
