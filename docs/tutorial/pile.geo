// A laterally loaded pile in a soil cylinder (docs/tutorial.md).
// Meridional half plane r >= 0: gmsh x = r, gmsh y = z, in metres.
//
//   z =   0  1-----2-------------------------------5   pile_head | soil_top
//            |     |                               |
//            |pile | pile_shaft (joint, r = a)     |
//            |     |                               |
//   z = -12  4-----3  pile_toe (joint, z = -L)     |   soil_side (fixed)
//            |                                     |
//            |                soil                 |
//   z = -24  7-------------------------------------6   soil_base (fixed)
//          r = 0  r = a = 0.6                   r = R = 12
//
// Parameters (axijoint --set NAME=VALUE, or gmsh -setnumber NAME VALUE):
//   h       element size along the two joints [m]
//   growth  increase of the element size per metre away from the joints [-]
//   hmax    largest element size [m]
//   L       pile length [m], 12 unless given
If (!Exists(h)) h = 0.3; EndIf
If (!Exists(growth)) growth = 0.25; EndIf
If (!Exists(hmax)) hmax = 3.0; EndIf

a = 0.6;    // pile radius
If (!Exists(L)) L = 12; EndIf  // pile length (head at z = 0)
R = 12;     // soil radius
H = 24;     // soil depth

Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};
Point(3) = {a, -L, 0};
Point(4) = {0, -L, 0};
Point(5) = {R, 0, 0};
Point(6) = {R, -H, 0};
Point(7) = {0, -H, 0};

Line(1) = {4, 3};   // pile_toe: axis -> toe corner
Line(2) = {2, 3};   // pile_shaft: head -> toe, so s along it is the depth
Line(3) = {2, 1};   // pile_head
Line(4) = {1, 4};   // axis (pile)
Line(5) = {7, 6};   // soil_base
Line(6) = {6, 5};   // soil_side
Line(7) = {5, 2};   // soil_top
Line(8) = {4, 7};   // axis (soil)

Curve Loop(1) = {1, -2, 3, 4};
Plane Surface(1) = {1};              // pile
Curve Loop(2) = {5, 6, 7, 2, -1, 8};
Plane Surface(2) = {2};              // soil

// Element size: h on the joints, growing linearly with the distance d
// from them, h + growth * d, up to hmax.
Field[1] = Distance;
Field[1].CurvesList = {1, 2};
Field[1].NumPointsPerCurve = 400;
Field[2] = MathEval;
Field[2].F = Sprintf("Min(%g + %g * F1, %g)", h, growth, hmax);
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

// Quadratic quadrilaterals (Q9).
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;

Physical Surface("pile") = {1};
Physical Surface("soil") = {2};
Physical Curve("pile_toe") = {1};
Physical Curve("pile_shaft") = {2};
Physical Curve("pile_head") = {3};
Physical Curve("axis") = {4, 8};
Physical Curve("soil_base") = {5};
Physical Curve("soil_side") = {6};
Physical Curve("soil_top") = {7};
