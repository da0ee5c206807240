// A slice of soil round a pile section: the annulus a <= r <= R, z in
// [0, L], for plane-strain studies of a pile moved sideways (top and
// bottom held in z). Meridional half plane: gmsh x = r, gmsh y = z.
//
//   z = L  +--------------------------+   top
//     pile |  soil (cells widen with r)| outer
//   z = 0  +--------------------------+   bottom
//        r = a                      r = R
//
// Parameters (gmsh -setnumber, or axijoint --set): a (pile radius, default
// 0.5), R (outer radius, default 10), L (slice thickness, default 0.1),
// n (cells along r, default 40), grading (outer cell width / inner,
// default 20), nz (cells along z, default 1), order (1|2), quads (0|1).
If (!Exists(a)) a = 0.5; EndIf
If (!Exists(R)) R = 10; EndIf
If (!Exists(L)) L = 0.1; EndIf
If (!Exists(n)) n = 40; EndIf
If (!Exists(grading)) grading = 20; EndIf
If (!Exists(nz)) nz = 1; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf

Point(1) = {a, 0, 0};
Point(2) = {R, 0, 0};
Point(3) = {R, L, 0};
Point(4) = {a, L, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {4, 3};
Line(4) = {1, 4};
Curve Loop(1) = {1, 2, -3, -4};
Plane Surface(1) = {1};
progression = 1;
If (n > 1) progression = grading^(1 / (n - 1)); EndIf
// The same progression outward on the bottom and the top: rectangles.
Transfinite Curve {1, 3} = n + 1 Using Progression progression;
Transfinite Curve {2, 4} = nz + 1;
Transfinite Surface {1} = {1, 2, 3, 4};

Mesh.ElementOrder = order;
Mesh.RecombineAll = quads;

Physical Surface("soil") = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2};
Physical Curve("top") = {3};
Physical Curve("pile") = {4};
