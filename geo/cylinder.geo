// Solid cylinder of radius a and length L (verification cases, docs/theory.md section 15).
// Meridional half plane: gmsh x = r, gmsh y = z.
//
//   z = L  +------+   top
//          |      |
//     axis | body | side
//          |      |
//   z = 0  o------+   bottom      o: physical point "origin"
//        r = 0  r = a
//
// Parameters (gmsh -setnumber): a, L, size, order (1|2), quads (0|1),
// serendipity (0|1), hole (inner radius: 0 for a solid cylinder, > 0 for a
// thick tube whose inner face is the curve "inner" instead of "axis"),
// split (0: one surface; 0 < split < L: two, the line z = split between
// them, e.g. at a water table).
If (!Exists(a)) a = 0.5; EndIf
If (!Exists(L)) L = 2.0; EndIf
If (!Exists(size)) size = 0.25; EndIf
If (!Exists(order)) order = 2; EndIf
If (!Exists(quads)) quads = 1; EndIf
If (!Exists(serendipity)) serendipity = 0; EndIf
If (!Exists(hole)) hole = 0; EndIf
If (!Exists(split)) split = 0; EndIf

If (split <= 0 || split >= L)
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
  sides[] = {2};
  axes[] = {4};
  surfaces[] = {1};
Else
  // Two layers, the line z = split between them.
  Point(1) = {hole, 0, 0, size};
  Point(2) = {a, 0, 0, size};
  Point(3) = {a, L, 0, size};
  Point(4) = {hole, L, 0, size};
  Point(5) = {a, split, 0, size};
  Point(6) = {hole, split, 0, size};
  Line(1) = {1, 2};
  Line(2) = {2, 5};
  Line(5) = {5, 3};
  Line(3) = {3, 4};
  Line(4) = {4, 6};
  Line(6) = {6, 1};
  Line(7) = {6, 5};
  Curve Loop(1) = {1, 2, -7, 6};
  Plane Surface(1) = {1};
  Curve Loop(2) = {7, 5, 3, 4};
  Plane Surface(2) = {2};
  sides[] = {2, 5};
  axes[] = {4, 6};
  surfaces[] = {1, 2};
EndIf

Mesh.ElementOrder = order;
Mesh.SecondOrderIncomplete = serendipity;
Mesh.RecombineAll = quads;

Physical Surface("body") = {surfaces[]};
Physical Curve("bottom") = {1};
Physical Curve("side") = {sides[]};
Physical Curve("top") = {3};
If (hole > 0)
  Physical Curve("inner") = {axes[]};
Else
  Physical Curve("axis") = {axes[]};
EndIf
Physical Point("origin") = {1};
