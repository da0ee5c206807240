// Scene P (docs/theory.md section 14): pile head embedded in a footing.
// Meridional half plane: gmsh x = r, gmsh y = z (metres).
//
//   z = 2.0  +------------------------------+        footing_top (free)
//            |                              |
//            |           footing            | footing_outer (fixed)
//   z = 1.0  +-----+ pile_head (bonded)     |
//            |     |                        |
//            |pile | pile_side (joint)      |
//   z = 0.0  |     +------------------------+ r = 3.0  footing_bottom (free)
//            |     |  pile_free
//   z =-1.5  +-----+  pile_end (loaded)
//          r = 0  r = 0.5
//
// Parameters (override with gmsh -setnumber NAME VALUE):
//   size        element size far from the pile side [m]
//   refine      size / (element size along the pile side)
//   order       1 = linear, 2 = quadratic elements
//   quads       1 = recombine into quadrilaterals, 0 = triangles
//   serendipity 1 = 8-node quadrilaterals (Q8) instead of Q9
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(refine)) refine = 2; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf

a = 0.5;       // pile radius
zend = -1.5;   // loaded pile end
zhead = 1.0;   // pile head
rf = 3.0;      // footing outer radius
hf = 2.0;      // footing height

Point(1) = {0, zend, 0, size};
Point(2) = {a, zend, 0, size};
Point(3) = {a, 0, 0, size / refine};
Point(4) = {a, zhead, 0, size / refine};
Point(5) = {0, zhead, 0, size / refine};
Point(6) = {rf, 0, 0, size};
Point(7) = {rf, hf, 0, size};
Point(8) = {0, hf, 0, size};

Line(1) = {1, 2};   // pile_end
Line(2) = {2, 3};   // pile_free
Line(3) = {3, 4};   // pile_side
Line(4) = {4, 5};   // pile_head
Line(5) = {5, 1};   // pile axis
Line(6) = {3, 6};   // footing_bottom
Line(7) = {6, 7};   // footing_outer
Line(8) = {7, 8};   // footing_top
Line(9) = {8, 5};   // footing axis

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {6, 7, 8, 9, -4, -3};
Plane Surface(2) = {2};

// Refine towards the pile side.
Field[1] = Distance;
Field[1].CurvesList = {3};
Field[1].NumPointsPerCurve = 100;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = size / refine;
Field[2].SizeMax = size;
Field[2].DistMin = 0.1;
Field[2].DistMax = 1.0;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
Mesh.RecombineAll = quads;

Physical Surface("pile") = {1};
Physical Surface("footing") = {2};
Physical Curve("pile_end") = {1};
Physical Curve("pile_free") = {2};
Physical Curve("pile_side") = {3};
Physical Curve("pile_head") = {4};
Physical Curve("axis") = {5, 9};
Physical Curve("footing_bottom") = {6};
Physical Curve("footing_outer") = {7};
Physical Curve("footing_top") = {8};
