// A pile through two soil layers: soft clay over stiff clay. Meridional
// half plane r >= 0: gmsh x = r, gmsh y = z (metres).
//
//   z =   0  +-----+----------------------------------+   pile_head | soil_top
//            |     | pile_side_soft (joint)    clay_soft|
//   z = zl   |pile +----------------------------------+   (layer boundary)
//            |     | pile_side_stiff (joint)  clay_stiff|   soil_outer (r = R)
//   z = -L   +-----+ pile_base (joint)                 |
//            |                                        |
//   z = -H   +----------------------------------------+   soil_bottom
//          r = 0  r = a                             r = R
//
// The pile's side meets two bodies, so it is two physical curves (one joint
// each, pile against one layer); they meet at (a, zl), where the node gets a
// copy for the pile and one for each layer.
//
// Parameters (axijoint --set NAME=VALUE):
//   size     element size along the pile [m]
//   coarsen  far-field element size / size
//   a, L     pile radius and length [m]
//   zl       depth of the layer boundary (negative) [m]
//   R, H     radius and depth of the soil [m]
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(coarsen)) coarsen = 8; EndIf
If (!Exists(a)) a = 0.5; EndIf
If (!Exists(L)) L = 15.0; EndIf
If (!Exists(zl)) zl = -6.0; EndIf
If (!Exists(R)) R = 15.0; EndIf
If (!Exists(H)) H = 30.0; EndIf
far = coarsen * size;

Point(1) = {0, 0, 0, size};
Point(2) = {a, 0, 0, size};
Point(3) = {a, zl, 0, size};
Point(4) = {a, -L, 0, size};
Point(5) = {0, -L, 0, size};
Point(6) = {R, 0, 0, far};
Point(7) = {R, zl, 0, far};
Point(8) = {R, -H, 0, far};
Point(9) = {0, -H, 0, far};

Line(1) = {5, 4};   // pile_base (joint)
Line(2) = {4, 3};   // pile_side_stiff (joint)
Line(3) = {3, 2};   // pile_side_soft (joint)
Line(4) = {2, 1};   // pile_head
Line(5) = {1, 5};   // pile axis
Line(6) = {2, 6};   // soil_top
Line(7) = {6, 7};   // soil_outer, soft layer
Line(8) = {7, 8};   // soil_outer, stiff layer
Line(9) = {8, 9};   // soil_bottom
Line(10) = {9, 5};  // soil axis
Line(11) = {3, 7};  // layer boundary

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 11, -7, -6};
Plane Surface(2) = {2};
Curve Loop(3) = {-2, -1, -10, -9, -8, -11};
Plane Surface(3) = {3};

Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Mesh.RecombineAll = 1;

Physical Surface("pile") = {1};
Physical Surface("clay_soft") = {2};
Physical Surface("clay_stiff") = {3};
Physical Curve("pile_base") = {1};
Physical Curve("pile_side_stiff") = {2};
Physical Curve("pile_side_soft") = {3};
Physical Curve("pile_head") = {4};
Physical Curve("soil_top") = {6};
Physical Curve("soil_outer") = {7, 8};
Physical Curve("soil_bottom") = {9};
Physical Curve("axis") = {5, 10};
