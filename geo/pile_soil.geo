// Pile in soil: a concrete pile, head flush with the soil surface, in a
// soil cylinder. Meridional half plane r >= 0: gmsh x = r, gmsh y = z (metres).
//
//   z =   0  +-----+----------------------------------+   pile_head (loaded) | soil_top (free)
//            |     |                                  |
//            |pile | pile_side (joint, r = a)         |
//            |     |                                  |
//   z = -10  +-----+ pile_base (joint, z = -L)        |   soil_outer (r = R, fixed)
//            |                                        |
//            |                 soil                   |
//            |                                        |
//   z = -20  +----------------------------------------+   soil_bottom (fixed)
//          r = 0  r = a = 0.5                      r = R = 10
//   axis: r = 0 (pile and soil)
//
// Joints: pile_side and pile_base are interfaces between the two bodies
// (declare them in the scene's "joints", or `axijoint mesh --joints
// pile_side,pile_base`). They meet at the pile toe corner (a, -L), where the
// soil wraps round the pile (the corner node gets one copy for the pile and
// one for the soil); pile_side reaches the free surface at (a, 0) and
// pile_base reaches the axis at (0, -L), where the node splits into a pile
// copy and a soil copy (crates/mesh/src/joints.rs, module doc).
//
// Parameters (override with gmsh -setnumber NAME VALUE, or axijoint --set):
//   a           pile radius [m] (default 0.5)
//   L           pile length [m] (default 10)
//   R           soil cylinder radius [m] (default 10)
//   H           soil depth [m] (default 20)
//   size        element size along the pile side and base [m]
//   coarsen     far-field element size / size (far size 2 m at the defaults)
//   order       1 = linear, 2 = quadratic elements
//   quads       1 = recombine into quadrilaterals, 0 = triangles
//   serendipity 1 = 8-node quadrilaterals (Q8) instead of Q9
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(coarsen)) coarsen = 8; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf

If (!Exists(a)) a = 0.5; EndIf  // pile radius
If (!Exists(L)) L = 10.0; EndIf  // pile length (head at z = 0, toe at z = -L)
If (!Exists(R)) R = 10.0; EndIf  // soil cylinder radius
If (!Exists(H)) H = 20.0; EndIf  // soil depth (bottom at z = -H)
far = coarsen * size;

Point(1) = {0, 0, 0, size};     // pile head centre (axis)
Point(2) = {a, 0, 0, size};     // pile head corner
Point(3) = {a, -L, 0, size};    // pile toe corner
Point(4) = {0, -L, 0, size};    // pile toe centre (axis)
Point(5) = {R, 0, 0, far};
Point(6) = {R, -H, 0, far};
Point(7) = {0, -H, 0, far};

Line(1) = {4, 3};   // pile_base (joint)
Line(2) = {3, 2};   // pile_side (joint)
Line(3) = {2, 1};   // pile_head
Line(4) = {1, 4};   // pile axis
Line(5) = {7, 6};   // soil_bottom
Line(6) = {6, 5};   // soil_outer
Line(7) = {5, 2};   // soil_top
Line(8) = {4, 7};   // soil axis

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};              // pile
Curve Loop(2) = {5, 6, 7, -2, -1, 8};
Plane Surface(2) = {2};              // soil

// Element size `size` along the joints, graded to `far` away from the pile.
Field[1] = Distance;
Field[1].CurvesList = {1, 2};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = size;
Field[2].SizeMax = far;
Field[2].DistMin = 2 * size;
Field[2].DistMax = 8.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
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
