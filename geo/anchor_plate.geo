// Anchor plate: a circular plate of radius b at depth H in a soil cylinder,
// pulled upward. Meridional half plane r >= 0: gmsh x = r, gmsh y = z (metres).
//
//   z = 0       +-----+-------------------------------+   plug_top | soil_top (free)
//               |     |                               |
//               |plug | cylinder (joint, r = b)       |
//               |     |                               |
//   z = -H      +=====+ plate_top (bonded)            |
//               |plate| plate_edge (joint, r = b)     |   soil_outer (r = R, fixed)
//   z = -H - t  +=====+ plate_bottom (joint)          |
//               |                                     |
//               |                soil                 |
//   z = -D      +-------------------------------------+   soil_bottom (fixed)
//             r = 0  r = b                          r = R
//   axis: r = 0 (plug, plate and soil)
//
// The soil above the plate (r < b) is a body of its own, "plug"; cylinder
// and plate_edge are its and the plate's interfaces with the surrounding
// "soil", plate_bottom the plate's with the soil below (declare them in the
// scene's "joints"). plate_top is not a joint: plug and plate share its
// nodes (a flat face for a "resultant" load on the plate). The joints split
// the nodes where they reach the surface (b, 0), the axis (0, -H - t) and
// the corners (b, -H) and (b, -H - t) (crates/mesh/src/joints.rs, module doc).
//
// Parameters (override with gmsh -setnumber NAME VALUE, or axijoint --set):
//   b, H, t     plate radius, depth of its top face, thickness [m]
//   R, D        soil cylinder radius and depth [m]
//   size        element size along the joints [m]
//   coarsen     far-field element size / size
//   order       1 = linear, 2 = quadratic elements
//   quads       1 = recombine into quadrilaterals, 0 = triangles
//   serendipity 1 = 8-node quadrilaterals (Q8) instead of Q9
If (!Exists(b)) b = 0.5; EndIf
If (!Exists(H)) H = 2.0; EndIf
If (!Exists(t)) t = 0.1; EndIf
If (!Exists(R)) R = 6.0; EndIf
If (!Exists(D)) D = 6.0; EndIf
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(coarsen)) coarsen = 4; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf
far = coarsen * size;

Point(1) = {0, 0, 0, size};          // plug top centre (axis)
Point(2) = {b, 0, 0, size};          // top of the cylinder
Point(3) = {b, -H, 0, size};         // plate top corner
Point(4) = {0, -H, 0, size};         // plate top centre (axis)
Point(5) = {b, -H - t, 0, size};     // plate bottom corner
Point(6) = {0, -H - t, 0, size};     // plate bottom centre (axis)
Point(7) = {R, 0, 0, far};
Point(8) = {R, -D, 0, far};
Point(9) = {0, -D, 0, far};

Line(1) = {4, 3};    // plate_top
Line(2) = {3, 2};    // cylinder (joint)
Line(3) = {2, 1};    // plug_top
Line(4) = {1, 4};    // plug axis
Line(5) = {6, 5};    // plate_bottom (joint)
Line(6) = {5, 3};    // plate_edge (joint)
Line(7) = {4, 6};    // plate axis
Line(8) = {9, 8};    // soil_bottom
Line(9) = {8, 7};    // soil_outer
Line(10) = {7, 2};   // soil_top
Line(11) = {6, 9};   // soil axis

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};                    // plug
Curve Loop(2) = {5, 6, -1, 7};
Plane Surface(2) = {2};                    // plate
Curve Loop(3) = {8, 9, 10, -2, -6, -5, 11};
Plane Surface(3) = {3};                    // soil

// The plate: one row of elements of about `size` across its radius.
nb = Ceil(b / size);
Transfinite Curve {1, 5} = nb + 1;
Transfinite Curve {6, 7} = 2;
Transfinite Surface {2} = {6, 5, 3, 4};

// Element size `size` along the joints, graded to `far` away from them.
Field[1] = Distance;
Field[1].CurvesList = {2, 5, 6};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = size;
Field[2].SizeMax = far;
Field[2].DistMin = 2 * size;
Field[2].DistMax = 4.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
Mesh.RecombineAll = quads;

Physical Surface("plate") = {2};
Physical Surface("plug") = {1};
Physical Surface("soil") = {3};
Physical Curve("plate_top") = {1};
Physical Curve("cylinder") = {2};
Physical Curve("plate_edge") = {6};
Physical Curve("plate_bottom") = {5};
Physical Curve("plug_top") = {3};
Physical Curve("soil_top") = {10};
Physical Curve("soil_bottom") = {8};
Physical Curve("soil_outer") = {9};
Physical Curve("axis") = {4, 7, 11};
