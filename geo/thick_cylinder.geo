// Cylinder r in [hole, a], z in [0, L] with a structured (transfinite) mesh:
// the twin of cylinder.geo for verification that needs parallelogram cells
// or nested refinements (docs/theory.md section 15: the Lame thick cylinder; exactness of
// the serendipity Q8, which reproduces quadratic fields only on
// parallelograms). Meridional half plane: gmsh x = r, gmsh y = z.
//
//   z = L  +--------+   top
//          |        |
//    inner |  body  | side
//          |        |
//   z = 0  +--------+   bottom
//       r = hole   r = a
//
// hole > 0: a thick tube, the curve r = hole is "inner".
// hole = 0: a solid cylinder, the curve r = 0 is "axis" and its bottom end
// the physical point "origin" (names as in cylinder.geo).
//
// Parameters (gmsh -setnumber): a, hole, L, size, order (1|2), quads (0|1),
// serendipity (0|1), transfinite (0|1), grading (>= 1, transfinite only).
// transfinite = 1: Round((a - hole) / size) by Round(L / size) cells, quads,
// or each quad cut along the same diagonal direction into two triangles;
// halving `size` nests the meshes, so convergence rates come out clean.
// grading: ratio of the last to the first cell width along the bottom
// (cells widen with r) and along the top (cells narrow with r); 1 gives
// rectangles, > 1 trapezoids (not parallelograms) on the smooth map
// r(s) = hole + (a - hole) (g^s - 1) / (g - 1) of a uniform grid, so that the
// cells stay distorted under refinement: bilinear (Q4) and serendipity (Q8)
// fields are then no longer exact.
// transfinite = 0: gmsh's unstructured mesher with target size `size`.
If (!Exists(a)) a = 1.0; EndIf
If (!Exists(hole)) hole = 0.5; EndIf
If (!Exists(L)) L = 0.5; EndIf
If (!Exists(size)) size = 0.125; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf
If (!Exists(transfinite)) transfinite = 1; EndIf
If (!Exists(grading)) grading = 1; EndIf

Point(1) = {hole, 0, 0, size};
Point(2) = {a, 0, 0, size};
Point(3) = {a, L, 0, size};
Point(4) = {hole, L, 0, size};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

If (transfinite)
  nr = Round((a - hole) / size);
  nz = Round(L / size);
  If (nr < 1) nr = 1; EndIf
  If (nz < 1) nz = 1; EndIf
  progression = 1;
  If (nr > 1) progression = grading^(1 / (nr - 1)); EndIf
  Transfinite Curve {1, 3} = nr + 1 Using Progression progression;
  Transfinite Curve {2, 4} = nz + 1;
  Transfinite Surface {1} = {1, 2, 3, 4};
EndIf

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
Mesh.RecombineAll = quads;

Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("side") = {2};
Physical Curve("top") = {3};
If (hole > 0)
  Physical Curve("inner") = {4};
Else
  Physical Curve("axis") = {4};
  Physical Point("origin") = {1};
EndIf
