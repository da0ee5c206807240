// Two solid cylinders of radius a stacked on the axis, lower z in [0, L1],
// upper z in [L1, L1 + L2], meeting on the horizontal curve "interface"
// (a joint in the verification cases of docs/theory.md section 15). Meridional half plane:
// gmsh x = r, gmsh y = z.
//
//   z = L1 + L2  +-------+   top
//                |       |
//         axis   | upper | side_upper
//                |       |
//   z = L1       +=======+   interface
//                |       |
//         axis   | lower | side_lower
//                |       |
//   z = 0        o-------+   bottom       o: physical point "origin"
//              r = 0   r = a
//
// Parameters (gmsh -setnumber): a, L1, L2, size, order (1|2), quads (0|1),
// serendipity (0|1).
If (!Exists(a)) a = 0.5; EndIf
If (!Exists(L1)) L1 = 1.0; EndIf
If (!Exists(L2)) L2 = 1.0; EndIf
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf

Point(1) = {0, 0, 0, size};
Point(2) = {a, 0, 0, size};
Point(3) = {a, L1, 0, size};
Point(4) = {0, L1, 0, size};
Point(5) = {a, L1 + L2, 0, size};
Point(6) = {0, L1 + L2, 0, size};
Line(1) = {1, 2};  // bottom
Line(2) = {2, 3};  // side_lower
Line(3) = {4, 3};  // interface, axis -> side
Line(4) = {4, 1};  // axis, lower part
Line(5) = {3, 5};  // side_upper
Line(6) = {5, 6};  // top
Line(7) = {6, 4};  // axis, upper part
Curve Loop(1) = {1, 2, -3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {3, 5, 6, 7};
Plane Surface(2) = {2};

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
Mesh.RecombineAll = quads;

Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("bottom") = {1};
Physical Curve("side_lower") = {2};
Physical Curve("interface") = {3};
Physical Curve("side_upper") = {5};
Physical Curve("top") = {6};
Physical Curve("axis") = {4, 7};
Physical Point("origin") = {1};
