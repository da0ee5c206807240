// Thick-walled cylinder (tube) for the Lame verification (DESIGN.md 6).
// Meridional half plane: gmsh x = r, gmsh y = z.
//
//   z = L  +--------+   top
//          |        |
//    inner |  tube  | outer
//          |        |
//   z = 0  +--------+   bottom
//        r = ai    r = b
//
// Parameters (gmsh -setnumber): ai (inner radius, > 0), b (outer radius),
// L (height), size (element size), order (1|2), quads (0|1),
// serendipity (0|1), transfinite (0|1).
// transfinite = 1 gives a structured mesh of Round((b - ai) / size) by
// Round(L / size) cells (quads, or each quad cut into two triangles along
// the same diagonal direction), so that halving `size` nests the meshes:
// convergence rates come out clean. transfinite = 0 leaves gmsh's
// unstructured mesher with target size `size`.
If (!Exists(ai)) ai = 0.5; EndIf
If (!Exists(b)) b = 1.0; EndIf
If (!Exists(L)) L = 0.5; EndIf
If (!Exists(size)) size = 0.125; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf
If (!Exists(transfinite)) transfinite = 1; EndIf

Point(1) = {ai, 0, 0, size};
Point(2) = {b, 0, 0, size};
Point(3) = {b, L, 0, size};
Point(4) = {ai, L, 0, size};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

If (transfinite)
  nr = Round((b - ai) / size);
  nz = Round(L / size);
  If (nr < 1) nr = 1; EndIf
  If (nz < 1) nz = 1; EndIf
  Transfinite Curve {1, 3} = nr + 1;
  Transfinite Curve {2, 4} = nz + 1;
  Transfinite Surface {1} = {1, 2, 3, 4};
EndIf

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
Mesh.RecombineAll = quads;

Physical Surface("tube") = {1};
Physical Curve("bottom") = {1};
Physical Curve("outer") = {2};
Physical Curve("top") = {3};
Physical Curve("inner") = {4};
